#include "recorder/fill_record.hpp"

#include <algorithm>

#include "session/device_session.hpp"
#include "session/state_flags.hpp"

namespace hapticd::server {

using recording::put;

void fill_cycle_record(recording::CycleRecord& r, const DeviceSession& session, std::uint16_t index,
                       const CycleTime& cycle, std::int64_t lateness_ns, std::int64_t compute_ns) noexcept {
  const DeviceSnapshot& s = session.published_snapshot();
  const DeviceState& state = session.state();
  r.cycle = cycle.index;
  r.time_ns = cycle.time_ns;
  r.device = index;
  r.dof = static_cast<std::uint8_t>(std::min<Eigen::Index>(state.joints.position.size(), kMaxJoints));
  r.mode = static_cast<std::uint8_t>(device_mode(s));
  r.flags = state_flags(s);
  r.scheme = static_cast<std::uint16_t>(s.scheme);
  put(r.position, s.position, r.dof);
  put(r.velocity, s.velocity, r.dof);
  put(r.torque_command, s.torque, r.dof);
  put(r.torque_measured, state.joints.effort, r.dof);
  put(r.handle_pose, s.handle_pose);
  put(r.handle_twist, s.handle_twist.linear, s.handle_twist.angular);
  r.buttons = s.buttons;
  r.gripper = s.gripper;
  put(r.operator_wrench, s.operator_wrench.force, s.operator_wrench.torque);
  put(r.environment_wrench, s.environment_wrench.force, s.environment_wrench.torque);
  put(r.sensor_wrench, state.sensor_wrench.force, state.sensor_wrench.torque);
  put(r.target_pose, s.target_pose);
  r.engine_weight = s.engine_weight;
  r.engine_sequence = s.engine_sequence;
  if (s.engine_has_proxy) {
    put(r.engine_proxy_pose, s.engine_proxy_pose);
  } else {
    std::fill(std::begin(r.engine_proxy_pose), std::end(r.engine_proxy_pose), 0.0);
  }
  if (s.engine_has_wrench) {
    put(r.engine_wrench, s.engine_wrench.force, s.engine_wrench.torque);
  } else {
    std::fill(std::begin(r.engine_wrench), std::end(r.engine_wrench), 0.0);
  }
  r.lateness_ns = lateness_ns;
  r.compute_ns = compute_ns;
}

}  // namespace hapticd::server
