#include "safety/safety_supervisor.hpp"

#include <algorithm>
#include <cmath>

namespace hapticd::server {

void SafetySupervisor::configure(const SafetySettings& settings, const DeviceDescription& description,
                                 double period_s) {
  settings_ = settings;
  const int dof = description.dof();
  peak_.resize(dof);
  continuous_.resize(dof);
  JointVector velocity_max(dof);
  for (int i = 0; i < dof; ++i) {
    const JointDescription& j = description.joints[static_cast<std::size_t>(i)];
    peak_[i] = j.torque_peak_nm;
    continuous_[i] =
        j.torque_continuous_nm > 0.0 ? std::min(j.torque_continuous_nm, j.torque_peak_nm) : j.torque_peak_nm;
    velocity_max[i] = j.velocity_max;
  }
  thermal_.configure(peak_, continuous_, settings.thermal_time_constant_s, settings.thermal_derate_from, period_s);
  motion_.configure(settings, velocity_max, description.interface == DeviceInterface::handle,
                    to_isometry(description.base_pose).linear());
  guard_.configure(period_s,
                   RenderLimits{settings.max_force_n, settings.max_torque_nm, settings.max_force_rate_n_per_s,
                                settings.max_torque_rate_nm_per_s},
                   settings.passivity_control, settings.passivity_max_damping_n_s_per_m,
                   settings.passivity_max_rotational_damping_n_m_s);
  history_.configure(settings.history_cycles, dof);
  soft_start_cycles_ = std::max<std::int64_t>(1, std::llround(settings.soft_start_s / period_s));
  soft_start_done_ = soft_start_cycles_;
  damping_cycles_ = std::llround(settings.safe_damping_s / period_s);
  fade_cycles_ = std::llround(settings.safe_fade_s / period_s);
  configured_hold_cycles_ = std::llround(settings.safe_hold_s / period_s);
  release_cycles_ = std::max<std::int64_t>(1, std::llround(settings.safe_release_s / period_s));
  hold_stiffness_ = continuous_ * (0.5 / settings.safe_hold_range);
  hold_posture_.setZero(dof);
  stall_ns_ = static_cast<std::int64_t>(std::llround(settings.max_stall_s * 1e9));
  fade_from_.setZero(dof);
  safe_cycles_ = damping_cycles_;
  zero_written_ = true;
}

void SafetySupervisor::restart_soft_start(const RenderGuard::Vector6& from) noexcept {
  soft_start_done_ = 0;
  guard_.reset(from);
  guard_.set_scale(0.0);  // already for this cycle
}

DeviceFault SafetySupervisor::begin_cycle(const JointVector& qd, const ChainState& chain,
                                          const Eigen::Vector3d& group_force) noexcept {
  if (soft_start_done_ < soft_start_cycles_) ++soft_start_done_;
  guard_.set_scale(static_cast<double>(soft_start_done_) / static_cast<double>(soft_start_cycles_));
  const DeviceFault f = motion_.check(qd, chain, handle_force_);
  handle_force_ += group_force;  // rendered (or applied as J^T F) with the supervisor's own
  guard_.begin_cycle(handle_force_);
  return f;
}

void SafetySupervisor::limit(const JointVector& qd, const ChainState& chain, JointVector& torque,
                             bool& saturated) noexcept {
  motion_.apply(qd, chain, handle_force_, guard_.safety_force_taken(), torque);
  const JointVector& lim = thermal_.limit();
  saturated = false;
  for (int i = 0; i < torque.size(); ++i) {
    const double t = std::clamp(torque[i], -lim[i], lim[i]);
    saturated = saturated || t != torque[i];
    torque[i] = t;
  }
  saturated_ = saturated;
}

std::uint32_t SafetySupervisor::flags() const noexcept {
  using namespace state_flag;
  return (saturated_ ? torque_saturated : 0u) | (motion_.engaged() ? limit_engaged : 0u) |
         (guard_.limited_this_cycle() ? render_limited : 0u) | (thermal_.derating() ? thermal_derating : 0u);
}

void SafetySupervisor::enter_safe_mode(const JointVector& last, const JointVector* hold_posture,
                                       bool skip_hold) noexcept {
  safe_cycles_ = 0;
  const bool gravity_hold = hold_posture != nullptr && hold_posture->size() == last.size() && hold_posture->allFinite();
  if (gravity_hold) hold_posture_ = *hold_posture;
  zero_written_ = false;
  fade_from_ = last;
  holding_gravity_ = gravity_hold && settings_.gravity_hold;
  hold_cycles_ = skip_hold ? 0 : configured_hold_cycles_;
}

double SafetySupervisor::hold_weight() const noexcept {
  if (!holding_gravity_) return 0.0;
  const std::int64_t release_from = damping_cycles_ + hold_cycles_;
  if (safe_cycles_ < release_from) return 1.0;
  // 1 - (k+1)/N over the release: the last release cycle commands zero gravity torque.
  return std::max(0.0,
                  1.0 - static_cast<double>(safe_cycles_ - release_from + 1) / static_cast<double>(release_cycles_));
}

void SafetySupervisor::safe_torque(const JointVector& position, const JointVector& velocity, bool velocity_valid,
                                   const JointVector* gravity, JointVector& torque) noexcept {
  const std::int64_t end = holding_gravity_ ? damping_cycles_ + hold_cycles_ + release_cycles_ : damping_cycles_;
  if (safe_cycles_ < end && (!velocity_valid || (holding_gravity_ && gravity == nullptr)))
    safe_cycles_ = end;  // untrusted: zero, for good
  if (safe_cycles_ < end) {
    // Fade: 1 - (k+1)/N, so the first safe cycle already steps down by one N-th and cycle N-1 reaches zero.
    const double fade = safe_cycles_ < fade_cycles_
                            ? 1.0 - static_cast<double>(safe_cycles_ + 1) / static_cast<double>(fade_cycles_)
                            : 0.0;
    const double hold = hold_weight();
    ++safe_cycles_;
    for (int i = 0; i < torque.size(); ++i) {
      // Holding: gravity compensation and a spring back to the posture at the stop (it reaches half the
      // continuous torque at safe_hold_range from it), released together.
      const double spring = std::clamp(hold_stiffness_[i] * (hold_posture_[i] - position[i]), -0.5 * continuous_[i],
                                       0.5 * continuous_[i]);
      const double held = hold > 0.0 ? hold * ((*gravity)[i] + spring) : 0.0;
      torque[i] = std::clamp(fade * fade_from_[i] + held -
                                 std::clamp(settings_.safe_damping_gain * velocity[i], -continuous_[i], continuous_[i]),
                             -peak_[i], peak_[i]);
    }
    zero_written_ = false;
    return;
  }
  torque.setZero();
  zero_written_ = true;
}

}  // namespace hapticd::server
