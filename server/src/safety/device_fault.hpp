#pragma once
// The reasons a device leaves normal operation for its safe mode, in the manner of a robot's reflex list:
// each has a stable code (events, the DDS state, logs) and a sentence for people.
#include <cstdint>
#include <string_view>

namespace hapticd::server {

enum class DeviceFault : std::uint8_t {
  none,
  device_read,             // the device's read() failed
  device_write,            // the device's write() failed
  non_finite_measurement,  // the device reported NaN or infinity
  sensor_saturation,       // the force/torque sensor reached its range
  activation,              // a plugin refused to activate
  configure,               // a plugin failed to configure: the device never ran
  device_enable,           // the device's enable() failed: it never ran
  device_homing,           // the device's home() failed: its positions are not absolute, it never ran
  virtual_model,           // the virtual model's update() returned an error
  inverse_kinematics,
  controller,
  plugin_exception,    // a plugin threw despite the real-time contract
  non_finite_output,   // a plugin produced NaN or infinity
  joint_velocity,      // a joint exceeded its velocity limit despite the damping
  cartesian_velocity,  // the handle exceeded its speed limit despite the damping
  workspace,           // the handle went through a workspace wall by more than the allowed depth
  loop_overrun,        // too many consecutive loop overruns
  loop_stall,          // the loop woke far too late (the process was stopped, the machine stalled)
  emergency_stop,      // requested (DDS, hapticctl, signal)
  collision,           // two devices of a group came closer than the group's hard minimum distance
  group_model,         // the group's model (bimanual coupling) failed, threw or produced a non-finite force
};

// The stable code ("joint_velocity_violation"); at most 31 characters.
[[nodiscard]] std::string_view fault_code(DeviceFault fault) noexcept;
// A sentence ("a joint exceeded its velocity limit").
[[nodiscard]] std::string_view to_string(DeviceFault fault) noexcept;
// What governs the fault and how to change it, for people ("" where nothing does: a plugin's failure, an E-stop):
// the device's setting ("safety.max_stall_s (0.02 s): --set devices.<device>.safety.max_stall_s=...").
[[nodiscard]] std::string_view governed_by(DeviceFault fault) noexcept;

}  // namespace hapticd::server
