#include "linear_axis_device.hpp"

#include <algorithm>
#include <cmath>

namespace example {

hapticd::ParameterSchema LinearAxisDevice::parameter_schema() {
  hapticd::ParameterSchema s;
  s.real("mass_kg", "the carriage's mass").unit("kg").greater_than(0.0).default_value(0.5);
  s.real("friction_n_s_per_m", "viscous friction of the rail").unit("N s/m").minimum(0.0).default_value(1.0);
  s.real("stroke_m", "the rail's length; the carriage starts in its middle")
      .unit("m")
      .greater_than(0.0)
      .default_value(0.2);
  s.real("peak_force_n", "the drive's peak force").unit("N").greater_than(0.0).default_value(20.0);
  return s;
}

void LinearAxisDevice::configure(const hapticd::Parameters& p, const hapticd::PluginContext&) {
  mass_kg_ = p.real("mass_kg");
  friction_ = p.real("friction_n_s_per_m");
  const double half = 0.5 * p.real("stroke_m");
  hapticd::JointDescription joint;
  joint.name = "carriage";
  joint.position_min = -half;
  joint.position_max = half;
  joint.velocity_max = 1.0;
  joint.torque_peak_nm = p.real("peak_force_n");
  joint.torque_continuous_nm = 0.5 * joint.torque_peak_nm;
  description_.model = "example_linear_axis";
  description_.joints = {joint};
  description_.reports_joint_velocity = true;
  description_.simulated = true;
}

hapticd::Outcome LinearAxisDevice::enable() {
  position_m_ = velocity_m_s_ = force_n_ = 0.0;
  time_ns_ = -1;
  return hapticd::Outcome::success();
}

hapticd::Outcome LinearAxisDevice::read(const hapticd::CycleTime& cycle, hapticd::DeviceState& state) {
  // The physics advances to the cycle's time under the last force written (zero-order hold), in 0.1 ms steps.
  if (time_ns_ < 0) time_ns_ = cycle.time_ns;
  while (time_ns_ < cycle.time_ns) {
    const std::int64_t step_ns = std::min<std::int64_t>(100'000, cycle.time_ns - time_ns_);
    const double dt = static_cast<double>(step_ns) * 1e-9;
    velocity_m_s_ += (force_n_ - friction_ * velocity_m_s_) / mass_kg_ * dt;
    position_m_ += velocity_m_s_ * dt;
    time_ns_ += step_ns;
  }
  const hapticd::JointDescription& joint = description_.joints.front();
  if (position_m_ < joint.position_min || position_m_ > joint.position_max)
    return hapticd::Outcome::failure("the carriage hit the end of its rail");
  state.timestamp_ns = cycle.time_ns;
  state.joints.resize(1);
  state.joints.position[0] = position_m_;
  state.joints.velocity[0] = velocity_m_s_;
  state.joints.effort[0] = force_n_;
  return hapticd::Outcome::success();
}

hapticd::Outcome LinearAxisDevice::write(const hapticd::CycleTime&, const hapticd::JointCommand& command) {
  const double f = command.torque_nm[0];
  if (!std::isfinite(f)) return hapticd::Outcome::failure("a non-finite force was commanded");
  const double peak = description_.joints.front().torque_peak_nm;
  force_n_ = std::clamp(f, -peak, peak);
  return hapticd::Outcome::success();
}

bool LinearAxisDevice::simulated_truth(hapticd::SimulatedTruth& out) const {
  out.time_s = static_cast<double>(std::max<std::int64_t>(time_ns_, 0)) * 1e-9;
  out.link_position.setConstant(1, position_m_);
  out.link_velocity.setConstant(1, velocity_m_s_);
  out.motor_position = out.link_position;  // a direct drive: no gear, no elasticity
  out.motor_velocity = out.link_velocity;
  out.friction_torque.setConstant(1, -friction_ * velocity_m_s_);
  out.motor_torque.setConstant(1, force_n_);
  return true;
}

}  // namespace example
