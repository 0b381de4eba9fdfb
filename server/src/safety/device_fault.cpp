#include "safety/device_fault.hpp"

namespace hapticd::server {

std::string_view fault_code(DeviceFault fault) noexcept {
  switch (fault) {
    case DeviceFault::none:
      return "none";
    case DeviceFault::device_read:
      return "device_read_error";
    case DeviceFault::device_write:
      return "device_write_error";
    case DeviceFault::non_finite_measurement:
      return "non_finite_measurement";
    case DeviceFault::sensor_saturation:
      return "sensor_saturation";
    case DeviceFault::activation:
      return "activation_failed";
    case DeviceFault::configure:
      return "configure_failed";
    case DeviceFault::device_enable:
      return "device_enable_failed";
    case DeviceFault::device_homing:
      return "device_homing_failed";
    case DeviceFault::virtual_model:
      return "virtual_model_error";
    case DeviceFault::inverse_kinematics:
      return "inverse_kinematics_error";
    case DeviceFault::controller:
      return "controller_error";
    case DeviceFault::plugin_exception:
      return "plugin_exception";
    case DeviceFault::non_finite_output:
      return "non_finite_output";
    case DeviceFault::joint_velocity:
      return "joint_velocity_violation";
    case DeviceFault::cartesian_velocity:
      return "cartesian_velocity_violation";
    case DeviceFault::workspace:
      return "workspace_violation";
    case DeviceFault::loop_overrun:
      return "loop_overrun_violation";
    case DeviceFault::loop_stall:
      return "loop_stall";
    case DeviceFault::emergency_stop:
      return "emergency_stop";
    case DeviceFault::collision:
      return "collision_distance_violation";
    case DeviceFault::group_model:
      return "group_model_failure";
  }
  return "unknown";
}

std::string_view to_string(DeviceFault fault) noexcept {
  switch (fault) {
    case DeviceFault::none:
      return "none";
    case DeviceFault::device_read:
      return "device read failed";
    case DeviceFault::device_write:
      return "device write failed";
    case DeviceFault::non_finite_measurement:
      return "device reported a non-finite value";
    case DeviceFault::sensor_saturation:
      return "the force/torque sensor saturated";
    case DeviceFault::activation:
      return "a plugin failed to activate";
    case DeviceFault::configure:
      return "a plugin failed to configure";
    case DeviceFault::device_enable:
      return "the device could not be enabled";
    case DeviceFault::device_homing:
      return "the device's homing failed";
    case DeviceFault::virtual_model:
      return "virtual model update failed";
    case DeviceFault::inverse_kinematics:
      return "inverse kinematics update failed";
    case DeviceFault::controller:
      return "controller update failed";
    case DeviceFault::plugin_exception:
      return "a plugin threw an exception in the loop";
    case DeviceFault::non_finite_output:
      return "a plugin produced a non-finite output";
    case DeviceFault::joint_velocity:
      return "a joint exceeded its velocity limit";
    case DeviceFault::cartesian_velocity:
      return "the handle exceeded its speed limit";
    case DeviceFault::workspace:
      return "the handle went through a workspace wall";
    case DeviceFault::loop_overrun:
      return "too many consecutive loop overruns";
    case DeviceFault::loop_stall:
      return "the loop stalled (it woke far too late for a cycle, or the device that clocks it stopped ticking)";
    case DeviceFault::emergency_stop:
      return "emergency stop";
    case DeviceFault::collision:
      return "two devices of a group came closer than their minimum distance";
    case DeviceFault::group_model:
      return "the group's model failed (an error, an exception or a non-finite force)";
  }
  return "unknown";
}

std::string_view governed_by(DeviceFault fault) noexcept {
  switch (fault) {
    case DeviceFault::joint_velocity:
      return "the device's safety.joint_fault_at (default 0.95) of each joint's velocity_max: --set "
             "devices.<device>.safety.joint_fault_at=...; an engine's MOTION is followed within the virtual model's "
             "engine_joint_speed_fraction";
    case DeviceFault::cartesian_velocity:
      return "the device's safety.max_speed_m_s (default 1.5): --set devices.<device>.safety.max_speed_m_s=...";
    case DeviceFault::workspace:
      return "the device's safety.workspace_min_m / workspace_max_m and wall_fault_depth_m";
    case DeviceFault::loop_overrun:
      return "the device's safety.max_consecutive_overruns (default 10): --set "
             "devices.<device>.safety.max_consecutive_overruns=...; a busy development machine with simulated "
             "devices: hapticd --busy-machine (docs/running.md)";
    case DeviceFault::loop_stall:
      return "the device's safety.max_stall_s (default 0.02 s): --set devices.<device>.safety.max_stall_s=...; a busy "
             "development machine with simulated devices: hapticd --busy-machine (docs/running.md)";
    case DeviceFault::sensor_saturation:
      return "the force/torque sensor's range (the device's description)";
    case DeviceFault::collision:
      return "the group's collision guard, its hard minimum distance (docs/multi-device.md)";
    case DeviceFault::emergency_stop:
      return "recover it with hapticctl recover <device> (docs/safety.md, \"Who may recover a stopped device\")";
    default:
      return "";
  }
}

}  // namespace hapticd::server
