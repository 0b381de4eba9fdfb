#pragma once
// The safety layer every device chain passes through (docs/safety.md), owned by the DeviceSession and run on
// the loop thread: it limits what the chain commands, watches what the device reports, and drives the safe
// mode after a fault. Real-time safe after configure(): fixed-size state only.
//
//   chain:   begin_cycle (soft-start scale for the rendered wrench) -> [virtual model: RenderGuard] ->
//            controller -> limit (velocity damping, workspace walls, thermal and peak torque) -> write -> written
//   fault:   enter_safe_mode -> safe_torque every cycle: joint damping for safe_damping_s, then zero torque
#include <cstdint>

#include "hapticd/chain_state.hpp"
#include "hapticd/device_description.hpp"
#include "hapticd/joint_vector.hpp"
#include "safety/device_fault.hpp"
#include "safety/fault_history.hpp"
#include "safety/motion_limits.hpp"
#include "safety/render_guard.hpp"
#include "safety/safety_settings.hpp"
#include "safety/thermal_limiter.hpp"

namespace hapticd::server {

class SafetySupervisor {
 public:
  void configure(const SafetySettings& settings, const DeviceDescription& description, double period_s);
  [[nodiscard]] const SafetySettings& settings() const noexcept { return settings_; }
  [[nodiscard]] RenderGuard& guard() noexcept { return guard_; }
  [[nodiscard]] const RenderGuard& guard() const noexcept { return guard_; }
  [[nodiscard]] FaultHistory& history() noexcept { return history_; }
  [[nodiscard]] const ThermalLimiter& thermal() const noexcept { return thermal_; }

  // The rendered-wrench limit ramps up from zero again (activation, scheme switch, recovery).
  void restart_soft_start(const RenderGuard::Vector6& from = RenderGuard::Vector6::Zero()) noexcept;
  // Start of a running cycle, before the chain: soft-start scale; speed and workspace checks (the fault they
  // raise, or none) and the handle force of the walls and speed damping, with the group's force (the arms'
  // repulsion), offered to the model (RenderGuard). qd: the joint-velocity estimate.
  DeviceFault begin_cycle(const JointVector& qd, const ChainState& chain, const Eigen::Vector3d& group_force) noexcept;
  // After the controller: joint velocity damping, the handle force unless the model took it to render
  // (RenderPort::take_safety_force this cycle), then the thermal and peak torque limits; `saturated` tells whether
  // the torque limit clamped.
  void limit(const JointVector& qd, const ChainState& chain, JointVector& torque, bool& saturated) noexcept;
  // The torque that was written: heats the thermal model.
  void written(const JointVector& torque) noexcept { thermal_.update(torque); }
  [[nodiscard]] bool overruns_exceeded(std::uint32_t consecutive) const noexcept {
    return settings_.max_consecutive_overruns > 0 && consecutive >= settings_.max_consecutive_overruns;
  }
  // This cycle's state flags of the safety layer (hapticd/state_flags.hpp: torque_saturated, limit_engaged,
  // render_limited, thermal_derating).
  [[nodiscard]] std::uint32_t flags() const noexcept;

  // Safe mode: the clock starts now. safe_torque() gives the last torque written (`last`, when it can be
  // trusted; else pass zero) fading linearly to zero over safe_fade_s, plus damping against `velocity`
  // bounded by each joint's continuous torque, for safe_damping_s; then zero. With gravity_hold (the device has
  // a robot model and the setting is on) the gravity torque is added and the damping continues for safe_hold_s
  // more (skip_hold: not at all, a stop of the server), then the gravity torque fades out over safe_release_s.
  // A cycle without a valid velocity (or gravity torque, when holding) ends it: zero torque from then on (no
  // step back up if the measurement returns).
  // hold_posture: the measured joint positions to hold (gravity_hold; nullptr: no hold).
  void enter_safe_mode(const JointVector& last, const JointVector* hold_posture = nullptr,
                       bool skip_hold = false) noexcept;
  void safe_torque(const JointVector& position, const JointVector& velocity, bool velocity_valid,
                   const JointVector* gravity, JointVector& torque) noexcept;
  // The safe mode's last torque was zero (the damping phase is over, or could not run; with gravity hold, the
  // release is over).
  [[nodiscard]] bool at_rest() const noexcept { return zero_written_; }
  // The safe mode has settled: the last torque has faded out and the damping phase is over (holding or at
  // rest). A recovery waits for it.
  [[nodiscard]] bool settled() const noexcept {
    return zero_written_ || (holding_gravity_ && safe_cycles_ >= damping_cycles_);
  }
  // The loop woke `lateness_ns` late for a cycle: a stall (max_stall_s)?
  [[nodiscard]] bool stalled(std::int64_t lateness_ns) const noexcept {
    return stall_ns_ > 0 && lateness_ns > stall_ns_;
  }

 private:
  SafetySettings settings_;
  ThermalLimiter thermal_;
  MotionLimits motion_;
  RenderGuard guard_;
  FaultHistory history_;
  JointVector peak_, continuous_;
  std::int64_t soft_start_cycles_ = 0;
  std::int64_t soft_start_done_ = 0;
  std::int64_t damping_cycles_ = 0;
  std::int64_t fade_cycles_ = 0;
  JointVector fade_from_;
  std::int64_t safe_cycles_ = 0;
  std::int64_t configured_hold_cycles_ = 0, hold_cycles_ = 0, release_cycles_ = 1;
  bool holding_gravity_ = false;
  JointVector hold_posture_, hold_stiffness_;
  std::int64_t stall_ns_ = 0;
  [[nodiscard]] double hold_weight() const noexcept;
  bool saturated_ = false;
  bool zero_written_ = true;
  Eigen::Vector3d handle_force_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::server
