#include "hapticd/teleop/energy_port.hpp"

#include <algorithm>

namespace hapticd::teleop {
namespace {

constexpr double kTiny = 1e-18;

}  // namespace

double EnergyPort::excess(double power, double dt, double available_in) const noexcept {
  // The power the budget cannot pay for this step: the energy out would pass what came in at the other port.
  const double room = std::max(0.0, available_in - out_);
  return std::max(0.0, power - room / dt);
}

void EnergyPort::account(double power_before, double power_after, double dt, double available_in) noexcept {
  if (power_after > 0.0) {
    out_ += power_after * dt;
  } else {
    in_ -= power_after * dt;
  }
  dissipated_ += (power_before - power_after) * dt;
  observed_ = available_in - out_;
}

Eigen::Vector3d EnergyPort::force_out(const Eigen::Vector3d& force, const Eigen::Vector3d& velocity, double dt,
                                      double available_in, bool control) noexcept {
  const double power = force.dot(velocity);
  const double speed2 = velocity.squaredNorm();
  Eigen::Vector3d applied = force;
  const double cut = control && speed2 > kTiny ? excess(power, dt, available_in) : 0.0;
  // F - alpha v with alpha |v|^2 = the excess power: |alpha v| <= |F|, never more than the force itself.
  if (cut > 0.0) applied -= (cut / speed2) * velocity;
  limiting_ = cut > 0.0;
  account(power, applied.dot(velocity), dt, available_in);
  return applied;
}

Eigen::Vector3d EnergyPort::velocity_out(const Eigen::Vector3d& velocity, const Eigen::Vector3d& reaction, double dt,
                                         double available_in, bool control) noexcept {
  const double power = -reaction.dot(velocity);
  const double force2 = reaction.squaredNorm();
  Eigen::Vector3d imposed = velocity;
  const double cut = control && force2 > kTiny ? excess(power, dt, available_in) : 0.0;
  if (cut > 0.0) imposed += (cut / force2) * reaction;
  limiting_ = cut > 0.0;
  account(power, -reaction.dot(imposed), dt, available_in);
  return imposed;
}

}  // namespace hapticd::teleop
