#include "jacobian_control.hpp"

#include "hapticd/model/task_space.hpp"
#include "hapticd/redundancy_resolution.hpp"

namespace hapticd::controllers {

ParameterSchema JacobianControl::parameter_schema() {
  ParameterSchema s;
  TaskMotionLaw::declare(s);
  s.real_vector("joint_inertia",
                "inverse_jacobian: constant diagonal joint inertia M_hat (empty: diag M at "
                "activation)")
      .default_value(std::vector<double>{});
  s.real_vector("task_mass",
                "transposed_jacobian: constant diagonal task-space mass Mx_hat, one per task row "
                "(empty: diag of the operational-space inertia at activation)")
      .default_value(std::vector<double>{});
  declare_friction_parameters(s);
  return s;
}

void JacobianControl::configure(const Parameters& p, const PluginContext& context) {
  law_.configure(p, context);
  friction_.configure(p, context);
  const int n = context.device->dof();
  const auto& mj = p.real_vector("joint_inertia");
  const auto& mx = p.real_vector("task_mass");
  const bool inverse = kind_ == Kind::inverse;
  const auto& given = inverse ? mj : mx;
  const int expected = inverse ? n : law_.rows();
  if (!given.empty() && static_cast<int>(given.size()) != expected) {
    throw ParameterError(inverse ? "joint_inertia" : "task_mass",
                         "needs " + std::to_string(expected) + " values, got " + std::to_string(given.size()));
  }
  for (double v : given) {
    if (!(v > 0.0)) throw ParameterError(inverse ? "joint_inertia" : "task_mass", "values must be positive");
  }
  inertia_from_model_ = given.empty();
  joint_inertia_.setZero(n);
  task_mass_.setZero(law_.rows());
  for (std::size_t i = 0; i < given.size(); ++i) {
    if (inverse) {
      joint_inertia_[static_cast<int>(i)] = given[i];
    } else {
      task_mass_[static_cast<int>(i)] = given[i];
    }
  }
}

Outcome JacobianControl::activate(const ControllerInput& current, const JointCommand&) {
  if (current.chain.model == nullptr) return Outcome::failure("Jacobian control needs the device's robot model");
  if (!inertia_from_model_) return Outcome::success();
  const model::ModelData& d = *current.chain.data;
  if (kind_ == Kind::inverse) {
    joint_inertia_ = d.mass_matrix.diagonal();
    return Outcome::success();
  }
  model::TaskMatrix lambda;
  const model::TaskJacobian j = d.frame_jacobian.topRows(law_.rows());
  if (!model::operational_space_inertia(d, j, lambda))
    return Outcome::failure("the device is at a singular configuration: no operational-space inertia");
  task_mass_ = lambda.diagonal();
  return Outcome::success();
}

Outcome JacobianControl::update(const CycleTime& /*cycle*/, const ControllerInput& in, JointCommand& command) {
  law_.take_tuned();  // run-time gains, at a cycle boundary
  const ChainState& c = in.chain;
  const model::ModelData& d = *c.data;
  if (!in.task.has_motion)
    return Outcome::failure("no desired motion: the scheme needs an admittance-type virtual model");
  const int rows = law_.rows();
  const model::TaskJacobian j = d.frame_jacobian.topRows(rows);
  if (kind_ == Kind::inverse) {
    const model::Vector6d xdd = law_.acceleration(in.task, c) - d.frame_jacobian_dot_qd;
    const model::TaskVector task(xdd.head(rows));
    const JointVector qdd = in.redundancy != nullptr ? in.redundancy->task_acceleration(in.device, c, task)
                                                     : model::minimum_norm_solution(j, task, damping_);
    command.torque_nm = joint_inertia_.cwiseProduct(qdd);
  } else {
    const model::Vector6d xdd = law_.acceleration(in.task, c);
    const model::TaskVector force = task_mass_.cwiseProduct(xdd.head(rows));
    command.torque_nm.noalias() = j.transpose() * force;
    // Redundant chains: the self-motion is left to the dynamically consistent null-space torque.
    if (in.redundancy != nullptr) command.torque_nm += in.redundancy->null_space_torque(in.device, c, rows);
  }
  command.torque_nm += d.gravity_torque;
  friction_.add(c, in.device.joints.velocity, rows, command.torque_nm);
  law_.add_wrench_compensation(c, command.torque_nm);
  return Outcome::success();
}

}  // namespace hapticd::controllers
