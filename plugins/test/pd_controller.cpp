#include "pd_controller.hpp"

#include <limits>

namespace hapticd::test_plugins {

ParameterSchema PdController::parameter_schema() {
  ParameterSchema s;
  s.real("kp", "proportional gain").unit("N/m").minimum(0.0).maximum(1e6).default_value(400.0);
  s.real("kd", "derivative gain").unit("N s/m").minimum(0.0).maximum(1e4).default_value(20.0);
  s.real("setpoint", "joint target used when the chain has no inverse kinematics").unit("m").default_value(0.0);
  s.integer("fault_at_cycle", "fault injection: output NaN at this cycle; -1 never").minimum(-1).default_value(-1);
  return s;
}

void PdController::configure(const Parameters& p, const PluginContext& context) {
  kp_ = p.real("kp");
  kd_ = p.real("kd");
  setpoint_ = p.real("setpoint");
  fault_at_cycle_ = p.integer("fault_at_cycle");
  dof_ = context.device != nullptr ? context.device->dof() : 0;
  if (dof_ == 0) throw ParameterError("kp", "the PD controller needs a device with at least one joint");
}

ReturnCode PdController::activate(const ControllerInput&, const JointCommand&) noexcept { return ReturnCode::ok; }

ReturnCode PdController::update(const CycleTime& cycle, const ControllerInput& in, JointCommand& command) noexcept {
  for (int i = 0; i < dof_; ++i) {
    const double q_d = in.joints.valid ? in.joints.position[i] : setpoint_;
    const double qd_d = in.joints.valid ? in.joints.velocity[i] : 0.0;
    command.torque_nm[i] = kp_ * (q_d - in.device.joints.position[i]) + kd_ * (qd_d - in.device.joints.velocity[i]);
  }
  if (fault_at_cycle_ >= 0 && cycle.index == static_cast<std::uint64_t>(fault_at_cycle_))
    command.torque_nm[0] = std::numeric_limits<double>::quiet_NaN();
  return ReturnCode::ok;
}

}  // namespace hapticd::test_plugins
