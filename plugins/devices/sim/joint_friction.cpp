#include "joint_friction.hpp"

#include <algorithm>
#include <cmath>

namespace hapticd::sim {

void JointFriction::configure(const FrictionParameters& p, std::uint64_t seed) {
  p_ = p;
  rng_.seed(seed);
  reset();
}

void JointFriction::reset() noexcept {
  temperature_c_ = p_.start_temperature_c;
  stuck_ = true;
  draw_breakaway();
}

void JointFriction::draw_breakaway() noexcept {
  const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
  breakaway_ = p_.scale * p_.size * (p_.breakaway_min_nm + u * (p_.breakaway_max_nm - p_.breakaway_min_nm));
}

double JointFriction::curve(int i, double speed) const noexcept {
  const auto& c = p_.curves[static_cast<std::size_t>(i)].p;
  const auto poly = [&](double v) { return (((c[4] * v + c[3]) * v + c[2]) * v + c[1]) * v + c[0]; };
  if (speed <= p_.fit_velocity_max) return poly(speed);
  const double v = p_.fit_velocity_max;
  const double slope = ((4 * c[4] * v + 3 * c[3]) * v + 2 * c[2]) * v + c[1];
  return poly(v) + std::max(0.0, slope) * (speed - v);
}

double JointFriction::sliding_magnitude(double speed, double load_torque) const noexcept {
  double f = 0.0;
  if (p_.sliding) {
    const auto& t = p_.temperatures_c;
    const double temp = std::clamp(temperature_c_, t[0], t[2]);
    const int i = temp <= t[1] ? 0 : 1;
    const double w =
        (temp - t[static_cast<std::size_t>(i)]) / (t[static_cast<std::size_t>(i) + 1] - t[static_cast<std::size_t>(i)]);
    f = p_.size * ((1.0 - w) * curve(i, speed) + w * curve(i + 1, speed));
  }
  if (p_.load_dependent) {
    const double l = std::abs(load_torque);
    f += p_.load_a2 * l * l + p_.load_a1 * l + p_.load_a0;
  }
  return p_.scale * std::max(0.0, f);
}

void JointFriction::advance_temperature(double dt) noexcept {
  if (!p_.warm_up) return;
  if (dt != decay_dt_) {  // the decay per step is computed once per step length
    decay_dt_ = dt;
    decay_ = std::exp(-dt / p_.warm_up_time_constant_s);
  }
  temperature_c_ = p_.end_temperature_c + (temperature_c_ - p_.end_temperature_c) * decay_;
}

double JointFriction::step_velocity(double velocity, double drive, double load_torque, double inertia, double dt,
                                    double& friction_out) noexcept {
  const bool any = p_.sliding || p_.load_dependent;
  if (!any && !p_.stiction) {
    friction_out = 0.0;
    stuck_ = false;
    return velocity + dt * drive / inertia;
  }
  if (p_.stiction && stuck_) {
    if (std::abs(drive) <= breakaway_) {
      friction_out = drive;  // static friction holds
      return 0.0;
    }
    stuck_ = false;
  }
  const double speed = std::abs(velocity);
  const double direction = speed > 0.0 ? std::copysign(1.0, velocity) : std::copysign(1.0, drive);
  const double f = sliding_magnitude(speed, load_torque);
  double v = velocity + dt * (drive - direction * f) / inertia;
  friction_out = direction * f;
  // Friction cannot reverse the motion: at a zero crossing the coordinate stops (and may stick).
  if (v * direction < 0.0 || (speed == 0.0 && std::abs(drive) <= f)) {
    v = 0.0;
    friction_out = drive;
    if (p_.stiction) {
      stuck_ = true;
      draw_breakaway();
    }
  }
  return v;
}

}  // namespace hapticd::sim
