#include "safety/safety_supervisor.hpp"

#include <algorithm>
#include <cmath>

namespace hapticd::server {

void SafetySupervisor::configure(const SafetySettings& settings, const DeviceDescription& description, double period_s) {
  settings_ = settings;
  const int dof = description.dof();
  peak_.resize(dof);
  continuous_.resize(dof);
  JointVector velocity_max(dof);
  for (int i = 0; i < dof; ++i) {
    const JointDescription& j = description.joints[static_cast<std::size_t>(i)];
    peak_[i] = j.torque_peak_nm;
    continuous_[i] = j.torque_continuous_nm > 0.0 ? std::min(j.torque_continuous_nm, j.torque_peak_nm) : j.torque_peak_nm;
    velocity_max[i] = j.velocity_max;
  }
  thermal_.configure(peak_, continuous_, settings.thermal_time_constant_s, settings.thermal_derate_from, period_s);
  motion_.configure(settings, velocity_max);
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
  fade_from_.setZero(dof);
  safe_cycles_ = damping_cycles_;
  zero_written_ = true;
}

void SafetySupervisor::restart_soft_start(const RenderGuard::Vector6& from) noexcept {
  soft_start_done_ = 0;
  guard_.reset(from);
  guard_.set_scale(0.0);  // already for this cycle
}

DeviceFault SafetySupervisor::begin_cycle(const ChainState& chain) noexcept {
  guard_.begin_cycle();
  if (soft_start_done_ < soft_start_cycles_) ++soft_start_done_;
  guard_.set_scale(static_cast<double>(soft_start_done_) / static_cast<double>(soft_start_cycles_));
  const DeviceFault f = motion_.check(chain, handle_force_);
  guard_.set_safety_force(handle_force_);
  return f;
}

void SafetySupervisor::limit(const ChainState& chain, JointVector& torque, bool& saturated) noexcept {
  motion_.apply(chain, handle_force_, guard_.safety_force_taken(), torque);
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
  return (saturated_ ? kRecordTorqueSaturated : 0u) | (motion_.engaged() ? kRecordLimitEngaged : 0u) |
         (guard_.limited_this_cycle() ? kRecordRenderLimited : 0u) | (thermal_.derating() ? kRecordThermalDerating : 0u);
}

void SafetySupervisor::safe_torque(const JointVector& velocity, bool velocity_valid, JointVector& torque) noexcept {
  if (safe_cycles_ < damping_cycles_ && !velocity_valid) safe_cycles_ = damping_cycles_;  // untrusted: zero, for good
  if (safe_cycles_ < damping_cycles_) {
    // Fade: 1 - (k+1)/N, so the first safe cycle already steps down by one N-th and cycle N-1 reaches zero.
    const double fade = safe_cycles_ < fade_cycles_
                            ? 1.0 - static_cast<double>(safe_cycles_ + 1) / static_cast<double>(fade_cycles_)
                            : 0.0;
    ++safe_cycles_;
    for (int i = 0; i < torque.size(); ++i)
      torque[i] = std::clamp(fade * fade_from_[i] - std::clamp(settings_.safe_damping_gain * velocity[i], -continuous_[i], continuous_[i]),
                             -peak_[i], peak_[i]);
    zero_written_ = false;
    return;
  }
  torque.setZero();
  zero_written_ = true;
}

}  // namespace hapticd::server
