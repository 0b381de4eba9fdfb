#include "pd_controller.hpp"

#include <limits>
#include <stdexcept>

#include "hapticd/demand.hpp"

namespace hapticd::test_plugins {

ParameterSchema PdController::parameter_schema() {
  ParameterSchema s;
  s.real("kp", "proportional gain").unit("N/m").minimum(0.0).maximum(1e6).default_value(400.0);
  s.real("kd", "derivative gain").unit("N s/m").minimum(0.0).maximum(1e4).default_value(20.0);
  s.real("setpoint", "joint target used when the chain has no inverse kinematics").unit("m").default_value(0.0);
  s.boolean("hold_at_activation",
            "without inverse kinematics: hold the joint positions of activation instead "
            "of the setpoint")
      .default_value(false);
  s.real("velocity_filter_hz", "devices without velocity: cut-off of the differentiated positions")
      .unit("Hz")
      .greater_than(0.0)
      .default_value(100.0);
  s.integer("fault_at_cycle", "fault injection: output NaN at this cycle; -1 never").minimum(-1).default_value(-1);
  s.integer("throw_at_cycle", "fault injection: update() throws at this cycle (against the contract); -1 never")
      .minimum(-1)
      .default_value(-1);
  s.boolean("throw_in_configure", "fault injection: configure() throws a plugin failure").default_value(false);
  s.boolean("throw_in_activate", "fault injection: activate() throws (against the contract)").default_value(false);
  s.boolean("throw_in_deactivate", "fault injection: deactivate() throws").default_value(false);
  return s;
}

void PdController::configure(const Parameters& p, const PluginContext& context) {
  kp_ = p.real("kp");
  kd_ = p.real("kd");
  setpoint_ = p.real("setpoint");
  fault_at_cycle_ = p.integer("fault_at_cycle");
  throw_at_cycle_ = p.integer("throw_at_cycle");
  throw_in_activate_ = p.boolean("throw_in_activate");
  throw_in_deactivate_ = p.boolean("throw_in_deactivate");
  if (p.boolean("throw_in_configure")) throw std::runtime_error("injected configure failure");
  hold_at_activation_ = p.boolean("hold_at_activation");
  dof_ = context.device != nullptr ? context.device->dof() : 0;
  if (dof_ == 0) throw ParameterError("kp", "the PD controller needs a device with at least one joint");
  differentiate_ = !context.device->reports_joint_velocity;
  differentiator_.configure(1.0 / context.rate_hz, p.real("velocity_filter_hz"));
  differentiator_.reset(JointVector::Zero(dof_));
  hold_.setConstant(dof_, setpoint_);
  velocity_.setZero(dof_);
}

Outcome PdController::activate(const ControllerInput& current, const JointCommand&) {
  if (throw_in_activate_) throw std::runtime_error("injected exception in activate()");
  if (hold_at_activation_) hold_ = current.device.joints.position;
  differentiator_.reset(current.device.joints.position);
  velocity_.setZero();
  return Outcome::success();
}

RuntimeReply PdController::handle_request(std::string_view name, const std::vector<double>& values) {
  HAPTICD_DEMAND(name != "break_invariant");  // fails on purpose for that request
  return Controller::handle_request(name, values);
}

void PdController::deactivate() {
  if (throw_in_deactivate_) throw std::runtime_error("injected deactivate failure (throw_in_deactivate)");
}

Outcome PdController::update(const CycleTime& cycle, const ControllerInput& in, JointCommand& command) {
  if (throw_at_cycle_ >= 0 && cycle.index == static_cast<std::uint64_t>(throw_at_cycle_))
    throw std::runtime_error("injected exception in update()");
  const JointVector& q = in.device.joints.position;
  if (differentiate_) {
    velocity_ = differentiator_.update(q);
  } else {
    velocity_ = in.device.joints.velocity;
  }
  for (int i = 0; i < dof_; ++i) {
    const double q_d = in.joints.valid ? in.joints.position[i] : hold_[i];
    const double qd_d = in.joints.valid ? in.joints.velocity[i] : 0.0;
    command.torque_nm[i] = kp_ * (q_d - q[i]) + kd_ * (qd_d - velocity_[i]);
  }
  if (fault_at_cycle_ >= 0 && cycle.index == static_cast<std::uint64_t>(fault_at_cycle_))
    command.torque_nm[0] = std::numeric_limits<double>::quiet_NaN();
  return Outcome::success();
}

}  // namespace hapticd::test_plugins
