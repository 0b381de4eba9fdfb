#include "trajectory_model.hpp"

#include <stdexcept>

#include "hapticd/chain_state.hpp"

namespace hapticd::models {

ParameterSchema TrajectoryModel::parameter_schema() {
  ParameterSchema s;
  s.string("path",
           "constant, step (at path_start_s), ramp (path_m per second), sine (amplitude path_m) or shuttle "
           "(out along path_m and back, trapezoidal velocity)")
      .choices({"constant", "step", "ramp", "sine", "shuttle"})
      .default_value(std::string("shuttle"));
  s.real_vector("path_m", "the path's value from the handle's position at activation (world axes)")
      .unit("m")
      .size(3)
      .default_value(std::vector<double>{0.1, 0, 0});
  s.real("path_start_s", "the path starts this long after the model's first cycle")
      .unit("s")
      .minimum(0.0)
      .default_value(0.5);
  s.real("path_frequency_hz", "sine: frequency").unit("Hz").greater_than(0.0).default_value(1.0);
  s.real("path_acceleration_m_s2", "shuttle: acceleration of the constant-acceleration phases")
      .unit("m/s^2")
      .greater_than(0.0)
      .default_value(1.0);
  s.real("path_speed_m_s", "shuttle: speed of the constant-velocity phases")
      .unit("m/s")
      .greater_than(0.0)
      .default_value(0.1);
  return s;
}

void TrajectoryModel::configure(const Parameters& p, const PluginContext&) {
  try {
    path_.kind = Profile::parse(p.string("path"));
  } catch (const std::invalid_argument& e) {
    throw ParameterError("path", e.what());
  }
  const auto& v = p.real_vector("path_m");
  path_.value = Eigen::Vector3d(v[0], v[1], v[2]);
  path_.start_s = p.real("path_start_s");
  path_.frequency_hz = p.real("path_frequency_hz");
  path_.acceleration = p.real("path_acceleration_m_s2");
  path_.speed = p.real("path_speed_m_s");
}

Outcome TrajectoryModel::activate(const VirtualModelInput& current) {
  start_ = current.chain.handle_pose;
  started_ = false;
  return Outcome::success();
}

Outcome TrajectoryModel::update(const CycleTime& cycle, const VirtualModelInput&, TaskTarget& target) {
  if (!started_) {
    started_ = true;
    start_ns_ = cycle.time_ns;
  }
  const double t = 1e-9 * static_cast<double>(cycle.time_ns - start_ns_);
  target.pose.position = start_.position + path_.at(t);
  target.pose.orientation = start_.orientation;
  target.twist.linear = path_.rate_at(t);
  target.twist.angular.setZero();
  target.acceleration.linear = path_.acceleration_at(t);
  target.acceleration.angular.setZero();
  target.wrench = Wrench{};
  target.has_motion = true;
  target.has_wrench = false;
  return Outcome::success();
}

}  // namespace hapticd::models
