#pragma once
// The power electronics and motor of one joint, at the joint output: the commanded torque is saturated at
// the peak torque, limited to the continuous torque while the thermal model is hot, offset by the amplifier's
// current offset, and delayed by the current loop (first-order lag, 2.5 kHz bandwidth by default).
// Real-time safe.
#include <cmath>

namespace hapticd::sim {

struct DriveParameters {
  double peak_torque = 54.0;        // [N m]
  double continuous_torque = 20.1;  // [N m]
  double current_bandwidth_hz = 2500.0;
  double thermal_time_constant_s = 30.0;  // I^2 t model of the winding
  double current_offset_nm = 0.0;         // direction asymmetry of friction tests (spec: about 0.2 N m)
  bool current_loop = true;
  bool thermal_limit = true;
};

class Drive {
 public:
  void configure(const DriveParameters& p) noexcept {
    p_ = p;
    reset();
  }
  void reset() noexcept {
    torque_ = 0.0;
    heat_ = 0.0;
  }

  // Advances by dt under the commanded torque; returns the torque the motor delivers.
  double step(double command, double dt) noexcept {
    const double limit = (p_.thermal_limit && heat_ >= 1.0) ? p_.continuous_torque : p_.peak_torque;
    const double target = std::fmax(-limit, std::fmin(limit, command)) + p_.current_offset_nm;
    if (p_.current_loop) {
      if (dt != alpha_dt_) {
        alpha_dt_ = dt;
        alpha_ = 1.0 - std::exp(-2.0 * M_PI * p_.current_bandwidth_hz * dt);
      }
      torque_ += alpha_ * (target - torque_);
    } else {
      torque_ = target;
    }
    // Normalised heat: 1 is the steady state of the continuous torque.
    const double load = torque_ / p_.continuous_torque;
    heat_ += dt / p_.thermal_time_constant_s * (load * load - heat_);
    return torque_;
  }
  [[nodiscard]] double torque() const noexcept { return torque_; }
  [[nodiscard]] double heat() const noexcept { return heat_; }
  [[nodiscard]] bool thermally_limited() const noexcept { return p_.thermal_limit && heat_ >= 1.0; }

 private:
  DriveParameters p_;
  double torque_ = 0.0;
  double heat_ = 0.0;
  double alpha_dt_ = -1.0;
  double alpha_ = 1.0;
};

}  // namespace hapticd::sim
