#include "sine_setpoint_model.hpp"

#include <cmath>
#include <numbers>

namespace hapticd::test_plugins {

ParameterSchema SineSetpointModel::parameter_schema() {
  ParameterSchema s;
  s.real("offset_m", "mean position").unit("m").minimum(-1.0).maximum(1.0).default_value(0.0);
  s.real("amplitude_m", "amplitude of the sine").unit("m").minimum(0.0).maximum(1.0);
  s.real("frequency_hz", "frequency of the sine").unit("Hz").minimum(0.0).maximum(100.0).default_value(1.0);
  return s;
}

void SineSetpointModel::configure(const Parameters& p, const PluginContext&) {
  offset_m_ = p.real("offset_m");
  amplitude_m_ = p.real("amplitude_m");
  frequency_hz_ = p.real("frequency_hz");
}

Outcome SineSetpointModel::activate(const VirtualModelInput&) { return Outcome::success(); }

Outcome SineSetpointModel::update(const CycleTime& cycle, const VirtualModelInput&, TaskTarget& target) {
  const double w = 2.0 * std::numbers::pi * frequency_hz_;
  const double t = cycle.time_s();
  target.pose.position.x() = offset_m_ + amplitude_m_ * std::sin(w * t);
  target.twist.linear.x() = amplitude_m_ * w * std::cos(w * t);
  target.acceleration.linear.x() = -amplitude_m_ * w * w * std::sin(w * t);
  target.has_motion = true;
  return Outcome::success();
}

}  // namespace hapticd::test_plugins
