#include "joint_space_control.hpp"

#include "hapticd/chain_state.hpp"
#include "hapticd/model/task_space.hpp"

namespace hapticd::controllers {

ParameterSchema JointSpaceControl::parameter_schema() {
  ParameterSchema s;
  model::declare_task_parameter(s, "rows of the operator-wrench compensation");
  s.real("bandwidth_rad_s", "computed_torque: error dynamics bandwidth w (Kp = w^2, Kd = 2 zeta w)")
      .unit("rad/s")
      .greater_than(0.0)
      .maximum(1000.0)
      .default_value(60.0);
  s.real("damping_ratio", "computed_torque: zeta").greater_than(0.0).maximum(5.0).default_value(1.0);
  s.real("joint_stiffness", "joint_pd: Kp").unit("N m/rad").minimum(0.0).default_value(500.0);
  s.real("joint_damping", "joint_pd: Kd").unit("N m s/rad").minimum(0.0).default_value(10.0);
  s.boolean("acceleration_feedforward", "computed_torque: add qdd_d").default_value(true);
  s.boolean("wrench_compensation", "cancel the measured operator wrench (- J^T F_h)").default_value(true);
  declare_friction_parameters(s);
  return s;
}

void JointSpaceControl::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.device->robot_model_file.empty()) {
    throw ParameterError("task", "joint-space admittance control needs a device with a robot model");
  }
  rows_ = model::task_rows(p.string("task"), context.device->dof());
  const double w = p.real("bandwidth_rad_s");
  kp_ = w * w;
  kd_ = 2.0 * p.real("damping_ratio") * w;
  joint_kp_ = p.real("joint_stiffness");
  joint_kd_ = p.real("joint_damping");
  acceleration_feedforward_ = p.boolean("acceleration_feedforward");
  wrench_compensation_ = p.boolean("wrench_compensation");
  friction_.configure(p, context);
  if (friction_.enabled() && kind_ == Kind::joint_pd) {
    throw ParameterError("friction_compensation", "joint_pd is the uncompensated baseline: use computed_torque");
  }
}

Outcome JointSpaceControl::activate(const ControllerInput& current, const JointCommand&) {
  return current.chain.model != nullptr ? Outcome::success()
                                        : Outcome::failure("joint-space control needs the device's robot model");
}

Outcome JointSpaceControl::update(const CycleTime& /*cycle*/, const ControllerInput& in, JointCommand& command) {
  const ChainState& c = in.chain;
  const model::ModelData& d = *c.data;
  if (!in.joints.valid) return Outcome::failure("no joint target: the scheme needs an inverse-kinematics plugin");
  const JointVector& q = in.device.joints.position;
  if (kind_ == Kind::computed_torque) {
    JointVector qdd = kp_ * (in.joints.position - q) + kd_ * (in.joints.velocity - in.device.joints.velocity);
    if (acceleration_feedforward_) qdd += in.joints.acceleration;
    command.torque_nm.noalias() = d.mass_matrix * qdd;
    command.torque_nm += d.coriolis_torque + d.gravity_torque;
    friction_.add(c, in.device.joints.velocity, rows_, command.torque_nm);
  } else {
    command.torque_nm = joint_kp_ * (in.joints.position - q) +
                        joint_kd_ * (in.joints.velocity - in.device.joints.velocity) + d.gravity_torque;
  }
  if (wrench_compensation_) command.torque_nm -= model::operator_wrench_torques(c, rows_);
  return Outcome::success();
}

}  // namespace hapticd::controllers
