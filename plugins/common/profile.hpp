#pragma once
// A scripted 3-D signal over time: constant, step at start_s, ramp from start_s, sine from start_s, or a shuttle
// (from start_s: out along `value` and back, again and again, each leg a trapezoidal velocity profile with
// constant-acceleration and constant-velocity phases: the backdrivability test's path).
// Used by the simulated device (the operator's target motion and voluntary force, the position source's path,
// scripted wrenches) and by the trajectory model (the desired handle path). Real-time safe.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>

namespace hapticd {

struct Profile {
  enum class Kind { constant, step, ramp, sine, ramp_to, shuttle };
  Kind kind = Kind::constant;
  Eigen::Vector3d value = Eigen::Vector3d::Zero();  // constant / step value, ramp rate per second, sine amplitude
  double start_s = 0.0;
  double frequency_hz = 1.0;
  Eigen::Vector3d from = Eigen::Vector3d::Zero();  // kRampTo: from `from` to `value` over duration_s
  double duration_s = 0.0;
  double acceleration = 1.0;  // kShuttle: acceleration and cruise speed along the leg [per s^2, per s]
  double speed = 0.1;

  [[nodiscard]] Eigen::Vector3d at(double t) const noexcept {
    switch (kind) {
      case Kind::constant:
        return value;
      case Kind::step:
        return t >= start_s ? value : Eigen::Vector3d::Zero();
      case Kind::ramp:
        return t >= start_s ? Eigen::Vector3d(value * (t - start_s)) : Eigen::Vector3d::Zero();
      case Kind::ramp_to: {
        const double a =
            duration_s > 0.0 ? std::clamp((t - start_s) / duration_s, 0.0, 1.0) : (t >= start_s ? 1.0 : 0.0);
        return from + a * (value - from);
      }
      case Kind::sine:
        return t >= start_s ? Eigen::Vector3d(value * std::sin(2.0 * M_PI * frequency_hz * (t - start_s)))
                            : Eigen::Vector3d::Zero();
      case Kind::shuttle:
        return value * shuttle(t)[0];
    }
    return Eigen::Vector3d::Zero();
  }
  [[nodiscard]] Eigen::Vector3d rate_at(double t) const noexcept {
    switch (kind) {
      case Kind::ramp_to:
        return duration_s > 0.0 && t >= start_s && t < start_s + duration_s
                   ? Eigen::Vector3d((value - from) / duration_s)
                   : Eigen::Vector3d::Zero();
      case Kind::ramp:
        return t >= start_s ? value : Eigen::Vector3d::Zero();
      case Kind::shuttle:
        return value * shuttle(t)[1];
      case Kind::sine:
        return t >= start_s ? Eigen::Vector3d(value * 2.0 * M_PI * frequency_hz *
                                              std::cos(2.0 * M_PI * frequency_hz * (t - start_s)))
                            : Eigen::Vector3d::Zero();
      default:
        return Eigen::Vector3d::Zero();
    }
  }
  // The second derivative (sine and shuttle; zero for the others, whose steps and kinks have none).
  [[nodiscard]] Eigen::Vector3d acceleration_at(double t) const noexcept {
    switch (kind) {
      case Kind::shuttle:
        return value * shuttle(t)[2];
      case Kind::sine: {
        const double w = 2.0 * M_PI * frequency_hz;
        return t >= start_s ? Eigen::Vector3d(-value * w * w * std::sin(w * (t - start_s))) : Eigen::Vector3d::Zero();
      }
      default:
        return Eigen::Vector3d::Zero();
    }
  }
  // "constant", "step", "ramp", "sine", "shuttle"; throws std::invalid_argument otherwise.
  static Kind parse(const std::string& name);

 private:
  // The shuttle's progress along `value` (0 .. 1), its rate and its acceleration at t.
  [[nodiscard]] Eigen::Vector3d shuttle(double t) const noexcept;
};

}  // namespace hapticd
