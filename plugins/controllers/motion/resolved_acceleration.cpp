#include "resolved_acceleration.hpp"

#include "hapticd/model/task_space.hpp"
#include "hapticd/redundancy_resolution.hpp"

namespace hapticd::controllers {

ParameterSchema ResolvedAcceleration::parameter_schema() {
  ParameterSchema s;
  TaskMotionLaw::declare(s);
  declare_friction_parameters(s);
  return s;
}

void ResolvedAcceleration::configure(const Parameters& p, const PluginContext& context) {
  law_.configure(p, context);
  friction_.configure(p, context);
}

Outcome ResolvedAcceleration::activate(const ControllerInput& current, const JointCommand&) {
  return current.chain.model != nullptr
             ? Outcome::success()
             : Outcome::failure("resolved-acceleration control needs the device's robot model");
}

Outcome ResolvedAcceleration::update(const CycleTime& /*cycle*/, const ControllerInput& in, JointCommand& command) {
  law_.take_tuned();  // run-time gains, at a cycle boundary
  const ChainState& c = in.chain;
  const model::ModelData& d = *c.data;
  if (!in.task.has_motion)
    return Outcome::failure("no desired motion: the scheme needs an admittance-type virtual model");
  const int rows = law_.rows();
  const model::Vector6d xdd = law_.acceleration(in.task, c) - d.frame_jacobian_dot_qd;
  // qdd = J^-1 (xdd - dJ qd) for square J; for redundant J the chain's redundancy resolution (its inverse, side
  // criteria and self-motion damping) if its IK offers one, else the minimum-norm solution.
  const model::TaskVector task(xdd.head(rows));
  const JointVector qdd = in.redundancy != nullptr
                              ? in.redundancy->task_acceleration(in.device, c, task)
                              : model::minimum_norm_solution(d.frame_jacobian.topRows(rows), task, damping_);
  command.torque_nm.noalias() = d.mass_matrix * qdd;
  command.torque_nm += d.coriolis_torque + d.gravity_torque;
  friction_.add(c, in.device.joints.velocity, rows, command.torque_nm);
  law_.add_wrench_compensation(c, command.torque_nm);
  return Outcome::success();
}

}  // namespace hapticd::controllers
