#pragma once
// Torsional stiffness of a harmonic drive, rising with load: k(d) = k_min + (k_max - k_min) min(1, |d| / d_r)
// over the deflection d, with d_r the deflection at which the data sheet's k_max is reached (rated torque
// over k_max). The torque is the integral of k, so the spring has a potential (energy is conserved).
#include <algorithm>
#include <cmath>

namespace hapticd::sim {

struct GearSpring {
  double k_min = 1e4;                      // [N m/rad]
  double k_max = 1.6e4;                    // [N m/rad]
  double rated_deflection = 39.0 / 1.6e4;  // [rad]

  [[nodiscard]] double torque(double d) const noexcept {
    const double a = std::abs(d);
    const double slope = (k_max - k_min) / rated_deflection;
    double t = 0.0;
    if (a <= rated_deflection) {
      t = k_min * a + 0.5 * slope * a * a;
    } else {
      t = k_min * rated_deflection + 0.5 * slope * rated_deflection * rated_deflection + k_max * (a - rated_deflection);
    }
    return std::copysign(t, d);
  }
  [[nodiscard]] double stiffness(double d) const noexcept {
    return k_min + (k_max - k_min) * std::min(1.0, std::abs(d) / rated_deflection);
  }
  [[nodiscard]] double potential(double d) const noexcept {
    const double a = std::abs(d);
    const double slope = (k_max - k_min) / rated_deflection;
    if (a <= rated_deflection) return 0.5 * k_min * a * a + slope * a * a * a / 6.0;
    const double r = rated_deflection;
    const double at_r = 0.5 * k_min * r * r + slope * r * r * r / 6.0;
    const double t_r = k_min * r + 0.5 * slope * r * r;
    const double e = a - r;
    return at_r + t_r * e + 0.5 * k_max * e * e;
  }
};

}  // namespace hapticd::sim
