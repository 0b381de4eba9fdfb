#include "safety/safety_settings.hpp"

namespace hapticd::server {

ParameterSchema safety_settings_schema() {
  ParameterSchema s;
  const SafetySettings d;
  s.real("thermal_time_constant_s",
         "time constant of the drives' thermal model; the torque limit falls from peak "
         "to continuous as the load reaches 1; off: no thermal limit")
      .unit("s")
      .greater_than(0.0)
      .maximum(3600.0)
      .can_be_off()
      .default_value(d.thermal_time_constant_s);
  s.real("thermal_derate_from", "thermal load at which the limit starts falling towards the continuous torque")
      .greater_than(0.0)
      .maximum(0.999)
      .default_value(d.thermal_derate_from);
  s.real("joint_damping_from", "fraction of a joint's velocity limit where damping injection starts")
      .greater_than(0.0)
      .maximum(1.0)
      .default_value(d.joint_damping_from);
  s.real("joint_fault_at", "fraction of a joint's velocity limit that faults the device")
      .greater_than(0.0)
      .maximum(2.0)
      .default_value(d.joint_fault_at);
  s.real("joint_damping_gain", "injected damping per unit of speed above joint_damping_from")
      .unit("N m s/rad")
      .minimum(0.0)
      .maximum(1e4)
      .default_value(d.joint_damping_gain);
  s.real("speed_damping_from_m_s", "handle speed where damping injection starts")
      .unit("m/s")
      .greater_than(0.0)
      .maximum(10.0)
      .default_value(d.speed_damping_from_m_s);
  s.real("max_speed_m_s", "handle speed that faults the device; off: no Cartesian speed limit")
      .unit("m/s")
      .greater_than(0.0)
      .maximum(10.0)
      .can_be_off()
      .default_value(d.max_speed_m_s);
  s.real("speed_damping_n_s_per_m", "injected damping per unit of handle speed above speed_damping_from_m_s")
      .unit("N s/m")
      .minimum(0.0)
      .maximum(1e4)
      .default_value(d.speed_damping_n_s_per_m);
  s.real_vector("workspace_min_m", "lower corner of the workspace box (world); the box is off when it is empty")
      .unit("m")
      .size(3)
      .minimum(-10.0)
      .maximum(10.0)
      .default_value(std::vector<double>{0.0, 0.0, 0.0});
  s.real_vector("workspace_max_m", "upper corner of the workspace box (world)")
      .unit("m")
      .size(3)
      .minimum(-10.0)
      .maximum(10.0)
      .default_value(std::vector<double>{0.0, 0.0, 0.0});
  s.real("wall_stiffness_n_per_m", "stiffness of the workspace walls")
      .unit("N/m")
      .minimum(0.0)
      .maximum(1e6)
      .default_value(d.wall_stiffness_n_per_m);
  s.real("wall_damping_n_s_per_m", "damping of the workspace walls (outward motion only)")
      .unit("N s/m")
      .minimum(0.0)
      .maximum(1e5)
      .default_value(d.wall_damping_n_s_per_m);
  s.real("wall_fault_depth_m", "depth beyond a workspace wall that faults the device")
      .unit("m")
      .greater_than(0.0)
      .maximum(1.0)
      .default_value(d.wall_fault_depth_m);
  s.real("max_force_n", "largest force the virtual environment may render")
      .unit("N")
      .greater_than(0.0)
      .maximum(2000.0)
      .default_value(d.max_force_n);
  s.real("max_torque_nm", "largest torque the virtual environment may render")
      .unit("N m")
      .greater_than(0.0)
      .maximum(500.0)
      .default_value(d.max_torque_nm);
  s.real("max_force_rate_n_per_s", "largest rate of change of the rendered force")
      .unit("N/s")
      .greater_than(0.0)
      .maximum(1e7)
      .default_value(d.max_force_rate_n_per_s);
  s.real("max_torque_rate_nm_per_s", "largest rate of change of the rendered torque")
      .unit("N m/s")
      .greater_than(0.0)
      .maximum(1e6)
      .default_value(d.max_torque_rate_nm_per_s);
  s.real("soft_start_s",
         "the rendered-wrench limit ramps up from zero over this time at activation, after a "
         "scheme switch and after a recovery")
      .unit("s")
      .minimum(0.0)
      .maximum(10.0)
      .default_value(d.soft_start_s);
  s.boolean("passivity_control", "passivity controller on the engine coupling port (the observer always runs)")
      .default_value(d.passivity_control);
  s.real("passivity_max_damping_n_s_per_m", "largest damping the passivity controller adds")
      .unit("N s/m")
      .minimum(0.0)
      .maximum(1e5)
      .default_value(d.passivity_max_damping_n_s_per_m);
  s.real("passivity_max_rotational_damping_n_m_s", "largest rotational damping the passivity controller adds")
      .unit("N m s/rad")
      .minimum(0.0)
      .maximum(1e4)
      .default_value(d.passivity_max_rotational_damping_n_m_s);
  s.integer("max_consecutive_overruns",
            "this many consecutive loop overruns put the device in its safe mode; off: "
            "never")
      .minimum(1)
      .maximum(100000)
      .can_be_off()
      .default_value(std::int64_t{d.max_consecutive_overruns});
  s.real("max_stall_s",
         "a loop that wakes this late for a cycle (the process was stopped or stalled) puts the "
         "device in its safe mode (fault loop_stall); off: no stall watchdog; real-time clock only")
      .unit("s")
      .greater_than(0.0)
      .maximum(1.0)
      .can_be_off()
      .default_value(d.max_stall_s);
  s.boolean("gravity_hold",
            "safe mode of a device with a robot model: hold the posture with gravity compensation "
            "and damping for safe_hold_s, then release the gravity torque over safe_release_s")
      .default_value(d.gravity_hold);
  s.real("safe_hold_s", "safe mode with gravity_hold: how long the posture is held")
      .unit("s")
      .minimum(0.0)
      .maximum(3600.0)
      .default_value(d.safe_hold_s);
  s.real("safe_hold_range",
         "safe mode with gravity_hold: a spring holds the posture at the stop; it gives half "
         "each joint's continuous torque (its limit) at this deviation")
      .unit("rad or m")
      .minimum(1e-4)
      .maximum(1.0)
      .default_value(d.safe_hold_range);
  s.real("safe_release_s", "safe mode with gravity_hold: the gravity torque fades out over this time after the hold")
      .unit("s")
      .minimum(0.0)
      .maximum(10.0)
      .default_value(d.safe_release_s);
  s.real("safe_fade_s",
         "safe mode: the last torque written fades linearly to zero over this time (no step); "
         "0: at once")
      .unit("s")
      .minimum(0.0)
      .maximum(1.0)
      .default_value(d.safe_fade_s);
  s.real("safe_damping_s", "safe mode: joint damping for this long, then zero torque")
      .unit("s")
      .minimum(0.0)
      .maximum(10.0)
      .default_value(d.safe_damping_s);
  s.real("safe_damping_gain", "safe mode: joint damping (bounded by each joint's continuous torque)")
      .unit("N m s/rad")
      .minimum(0.0)
      .default_value(d.safe_damping_gain);
  s.integer("history_cycles", "cycles of state a fault event carries")
      .minimum(1)
      .maximum(std::int64_t{kMaxHistoryCycles})
      .default_value(std::int64_t{d.history_cycles});
  return s;
}

SafetySettings safety_settings_from(const Parameters& p) {
  SafetySettings s;
  s.thermal_time_constant_s = p.real("thermal_time_constant_s");
  s.thermal_derate_from = p.real("thermal_derate_from");
  s.joint_damping_from = p.real("joint_damping_from");
  s.joint_fault_at = p.real("joint_fault_at");
  if (s.joint_fault_at <= s.joint_damping_from)
    throw ParameterError("joint_fault_at", "must be above joint_damping_from (damping comes before the fault)");
  s.joint_damping_gain = p.real("joint_damping_gain");
  s.speed_damping_from_m_s = p.real("speed_damping_from_m_s");
  s.max_speed_m_s = p.real("max_speed_m_s");
  if (s.max_speed_m_s > 0.0 && s.max_speed_m_s <= s.speed_damping_from_m_s)
    throw ParameterError("max_speed_m_s", "must be above speed_damping_from_m_s (damping comes before the fault)");
  s.speed_damping_n_s_per_m = p.real("speed_damping_n_s_per_m");
  const auto lo = p.real_vector("workspace_min_m"), hi = p.real_vector("workspace_max_m");
  for (std::size_t i = 0; i < 3; ++i) {
    s.workspace_min_m[i] = lo[i];
    s.workspace_max_m[i] = hi[i];
  }
  bool any = false, all = true;
  for (std::size_t i = 0; i < 3; ++i) {
    any = any || lo[i] != hi[i];
    all = all && lo[i] < hi[i];
  }
  if (any && !all) throw ParameterError("workspace_max_m", "must lie above workspace_min_m on every axis");
  s.wall_stiffness_n_per_m = p.real("wall_stiffness_n_per_m");
  s.wall_damping_n_s_per_m = p.real("wall_damping_n_s_per_m");
  s.wall_fault_depth_m = p.real("wall_fault_depth_m");
  s.max_force_n = p.real("max_force_n");
  s.max_torque_nm = p.real("max_torque_nm");
  s.max_force_rate_n_per_s = p.real("max_force_rate_n_per_s");
  s.max_torque_rate_nm_per_s = p.real("max_torque_rate_nm_per_s");
  s.soft_start_s = p.real("soft_start_s");
  s.passivity_control = p.boolean("passivity_control");
  s.passivity_max_damping_n_s_per_m = p.real("passivity_max_damping_n_s_per_m");
  s.passivity_max_rotational_damping_n_m_s = p.real("passivity_max_rotational_damping_n_m_s");
  s.max_consecutive_overruns = static_cast<std::uint32_t>(p.integer("max_consecutive_overruns"));
  s.max_stall_s = p.real("max_stall_s");
  s.gravity_hold = p.boolean("gravity_hold");
  s.safe_hold_s = p.real("safe_hold_s");
  s.safe_release_s = p.real("safe_release_s");
  s.safe_hold_range = p.real("safe_hold_range");
  s.safe_fade_s = p.real("safe_fade_s");
  s.safe_damping_s = p.real("safe_damping_s");
  if (s.safe_damping_s < s.safe_fade_s) throw ParameterError("safe_damping_s", "must not be shorter than safe_fade_s");
  s.safe_damping_gain = p.real("safe_damping_gain");
  s.history_cycles = static_cast<std::uint32_t>(p.integer("history_cycles"));
  return s;
}

}  // namespace hapticd::server
