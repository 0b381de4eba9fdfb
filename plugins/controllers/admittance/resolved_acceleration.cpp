#include "resolved_acceleration.hpp"

#include <Eigen/Cholesky>

namespace hapticd::controllers {

ParameterSchema ResolvedAcceleration::parameter_schema() {
  ParameterSchema s;
  TaskMotionLaw::declare(s);
  return s;
}

void ResolvedAcceleration::configure(const Parameters& p, const PluginContext& context) { law_.configure(p, context); }

ReturnCode ResolvedAcceleration::activate(const ControllerInput& current, const JointCommand&) noexcept {
  return current.chain != nullptr && current.chain->model != nullptr ? ReturnCode::ok : ReturnCode::error;
}

ReturnCode ResolvedAcceleration::update(const CycleTime& /*cycle*/, const ControllerInput& in,
                                        JointCommand& command) noexcept {
  const ChainState& c = *in.chain;
  const model::ModelData& d = *c.data;
  if (!in.task.has_motion) return ReturnCode::error;
  const int rows = law_.rows();
  const model::Vector6d xdd = law_.acceleration(in.task, c) - d.frame_jacobian_dot_qd;
  const model::TaskJacobian j = d.frame_jacobian.topRows(rows);
  // qdd = J^T (J J^T + l I)^-1 (xdd - dJ qd): the inverse for square J, minimum norm for redundant J.
  model::TaskMatrix jjt = j * j.transpose();
  jjt.diagonal().array() += damping_;
  const model::TaskVector task_acceleration = xdd.head(rows);
  const model::TaskVector weights = jjt.ldlt().solve(task_acceleration);
  JointVector qdd = JointVector::Zero(j.cols());
  qdd.noalias() = j.transpose() * weights;
  command.torque_nm.noalias() = d.mass_matrix * qdd;
  command.torque_nm += d.coriolis_torque + d.gravity_torque;
  law_.add_wrench_compensation(c, command.torque_nm);
  return ReturnCode::ok;
}

}  // namespace hapticd::controllers
