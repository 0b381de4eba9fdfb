#pragma once
// A point-to-point move with a trapezoidal velocity profile (accelerate, cruise, decelerate). Real-time safe.
#include <algorithm>
#include <cmath>

namespace hapticd::controllers {

struct TrapezoidMove {
  double start = 0.0, distance = 0.0;  // [rad], signed
  double speed = 1.0, acceleration = 10.0;

  [[nodiscard]] double accel_time() const noexcept { return speed / acceleration; }
  [[nodiscard]] double cruise_time() const noexcept { return std::max(0.0, std::abs(distance) / speed - accel_time()); }
  [[nodiscard]] double duration() const noexcept { return 2.0 * accel_time() + cruise_time(); }
  // The stroke must be long enough to reach the cruise speed.
  [[nodiscard]] static bool reaches_speed(double distance, double speed, double acceleration) noexcept {
    return std::abs(distance) >= speed * speed / acceleration;
  }

  // Position, velocity and acceleration at time t since the move's start.
  void at(double t, double& q, double& qd, double& qdd) const noexcept {
    const double dir = distance >= 0.0 ? 1.0 : -1.0;
    const double ta = accel_time(), tc = cruise_time(), te = duration();
    t = std::clamp(t, 0.0, te);
    double s, v, a;
    if (t < ta) {
      s = 0.5 * acceleration * t * t, v = acceleration * t, a = acceleration;
    } else if (t < ta + tc) {
      s = 0.5 * speed * ta + speed * (t - ta), v = speed, a = 0.0;
    } else if (t < te) {
      const double r = te - t;
      s = std::abs(distance) - 0.5 * acceleration * r * r, v = acceleration * r, a = -acceleration;
    } else {
      s = std::abs(distance), v = 0.0, a = 0.0;
    }
    q = start + dir * s;
    qd = dir * v;
    qdd = dir * a;
  }
};

}  // namespace hapticd::controllers
