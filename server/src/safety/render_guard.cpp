#include "safety/render_guard.hpp"

#include <algorithm>
#include <cmath>

namespace hapticd::server {
namespace {

// Limits a 3-vector's magnitude to `max` and its change from `last` to `max_step`. True if it changed it.
bool limit_vector(Eigen::Vector3d& v, const Eigen::Vector3d& last, double max, double max_step) noexcept {
  bool changed = false;
  if (const double n = v.norm(); n > max) {
    v *= max / n;
    changed = true;
  }
  const Eigen::Vector3d step = v - last;
  if (const double s = step.norm(); s > max_step) {
    v = last + step * (max_step / s);
    changed = true;
  }
  return changed;
}

}  // namespace

Eigen::Vector3d PassivityPort::filter(const Eigen::Vector3d& force, const Eigen::Vector3d& velocity, double dt,
                                      bool control, double max_damping) noexcept {
  // The device side gives energy to the environment at the rate -f.v (f acts on the device side).
  energy_j_ -= force.dot(velocity) * dt;
  if (!control || energy_j_ >= 0.0) return force;
  const double v2 = velocity.squaredNorm();
  if (v2 < 1e-12) return force;
  // The damping that dissipates the whole excess this step, bounded.
  const double alpha = std::min(-energy_j_ / (dt * v2), max_damping);
  const double dissipated = alpha * v2 * dt;
  energy_j_ += dissipated;
  dissipated_j_ += dissipated;
  return force - alpha * velocity;
}

void RenderGuard::configure(double period_s, const RenderLimits& limits, bool passivity_control, double max_damping,
                            double max_rotational_damping) noexcept {
  dt_ = period_s;
  limits_ = limits;
  passivity_control_ = passivity_control;
  max_damping_ = max_damping;
  max_rotational_damping_ = max_rotational_damping;
}

void RenderGuard::reset(const Vector6& from) noexcept {
  last_ = from;
  linear_.reset();
  angular_.reset();
}

RenderGuard::Vector6 RenderGuard::engine_port(const Vector6& wrench, const Vector6& port_twist) noexcept {
  Vector6 out;
  out.head<3>() = linear_.filter(wrench.head<3>(), port_twist.head<3>(), dt_, passivity_control_, max_damping_);
  out.tail<3>() =
      angular_.filter(wrench.tail<3>(), port_twist.tail<3>(), dt_, passivity_control_, max_rotational_damping_);
  return out;
}

RenderGuard::Vector6 RenderGuard::limit(const Vector6& wrench) noexcept {
  Eigen::Vector3d force = wrench.head<3>(), torque = wrench.tail<3>();
  const bool f =
      limit_vector(force, last_.head<3>(), scale_ * limits_.max_force_n, limits_.max_force_rate_n_per_s * dt_);
  const bool t =
      limit_vector(torque, last_.tail<3>(), scale_ * limits_.max_torque_nm, limits_.max_torque_rate_nm_per_s * dt_);
  last_ << force, torque;
  limited_this_cycle_ = limited_this_cycle_ || f || t;
  limit_applied_ = true;
  return last_;
}

}  // namespace hapticd::server
