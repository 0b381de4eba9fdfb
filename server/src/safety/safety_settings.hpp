#pragma once
// A device's `safety` section (docs/safety.md): the limits and watchdogs of the safety supervisor on top of the
// limits the plugins respect. Every entry has a default; joint limits come from the device's description.
#include <array>
#include <cstdint>

#include "hapticd/parameters.hpp"

namespace hapticd::server {

struct SafetySettings {
  // Torque: peak from the description; continuous through a first-order thermal model per joint.
  double thermal_time_constant_s = 30.0;  // 0: no thermal limit
  double thermal_derate_from = 0.9;       // thermal load (1 = continuous torque forever) where derating begins
  // Joint velocity: damping from a fraction of each joint's velocity_max, fault at another.
  double joint_damping_from = 0.75;
  double joint_fault_at = 0.95;
  double joint_damping_gain = 2.0;  // N m s/rad (N s/m) per unit of excess speed
  // Cartesian velocity of the handle (devices with a robot model).
  double speed_damping_from_m_s = 1.0;
  double max_speed_m_s = 1.5;  // fault above; 0: no Cartesian speed limit
  double speed_damping_n_s_per_m = 60.0;
  // Workspace walls: an axis-aligned box in world coordinates; off when min >= max on every axis.
  std::array<double, 3> workspace_min_m{0.0, 0.0, 0.0};
  std::array<double, 3> workspace_max_m{0.0, 0.0, 0.0};
  double wall_stiffness_n_per_m = 3000.0;
  double wall_damping_n_s_per_m = 30.0;
  double wall_fault_depth_m = 0.03;
  // The rendered wrench (what the virtual environment applies to the handle) and its rate of change.
  double max_force_n = 80.0;
  double max_torque_nm = 4.0;
  double max_force_rate_n_per_s = 4000.0;
  double max_torque_rate_nm_per_s = 200.0;
  // Soft start: the rendered-wrench limit ramps up from zero over this time at activation, after a scheme
  // switch and after a recovery.
  double soft_start_s = 0.2;
  // Passivity observer (always) and controller (off by default: it also takes away energy an engine's world
  // gives on purpose - a weight, a moving object) on the engine coupling port.
  bool passivity_control = false;
  double passivity_max_damping_n_s_per_m = 200.0;
  double passivity_max_rotational_damping_n_m_s = 2.0;
  // Watchdogs.
  std::uint32_t max_consecutive_overruns = 10;  // 0: overruns never stop the device
  // A loop that wakes this late for a cycle (the process was stopped, the machine stalled) faults the device
  // with loop_stall; 0: off. Real-time clock only.
  double max_stall_s = 0.02;
  // Safe mode: the last torque written fades out over safe_fade_s (no step) while joint damping acts for
  // safe_damping_s; then zero torque.
  double safe_fade_s = 0.02;
  double safe_damping_s = 0.5;
  double safe_damping_gain = 3.0;  // N m s/rad (N s/m), bounded by each joint's continuous torque
  // Devices with a robot model hold their posture in the safe mode: gravity compensation plus damping (from
  // the measured state) for safe_hold_s, then the gravity torque fades out over safe_release_s (the device has
  // no brakes yet) and the torque is zero. A stop of the server skips the hold.
  bool gravity_hold = true;
  double safe_hold_s = 10.0;
  double safe_release_s = 0.5;
  double safe_hold_range = 0.02;  // rad (m): the hold's posture spring gives half the continuous torque here
  // The fault event carries this many cycles of history.
  std::uint32_t history_cycles = 50;
};

inline constexpr std::uint32_t kMaxHistoryCycles = 64;

// The schema of a device's `safety` section: validates it and documents it (hapticd --describe-config).
ParameterSchema safety_settings_schema();
// Settings from validated parameters (cross-checks throw ParameterError naming the key).
SafetySettings safety_settings_from(const Parameters& parameters);

}  // namespace hapticd::server
