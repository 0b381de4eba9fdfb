#pragma once
// A scripted wrench over time, the excitation of the evaluation suite's force experiments: a direction (force
// and torque, world) scaled by a signal s(t) that starts at start_s and is zero before:
//   constant  s = 1
//   sine      s = sin(2 pi f t')                                   t' = t - start_s
//   chirp     s = sin(2 pi (f0 t' + (f1 - f0) t'^2 / (2 T)))       linear sweep f0 -> f1 over T, then 0
//   steps     s = levels[k] for k = floor(t' / step_s)             each level held step_s, the last one kept
// Real-time safe: no allocation after set-up.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace hapticd::models {

class WrenchScript {
 public:
  enum class Signal { constant, sine, chirp, steps };
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  static constexpr int kMaxLevels = 32;

  struct Settings {
    Signal signal = Signal::sine;
    Vector6 direction = Vector6::Zero();  // [force N; torque N m], the amplitude of the signal
    double start_s = 0.0;
    double frequency_hz = 1.0;                                                  // sine
    double chirp_start_hz = 1.0, chirp_end_hz = 60.0, chirp_duration_s = 10.0;  // chirp
    std::vector<double> levels;                                                 // steps (at most kMaxLevels)
    double step_s = 1.0;                                                        // steps
  };

  // Throws std::invalid_argument naming what is wrong (an unknown signal, too many levels, ...).
  void configure(const Settings& settings);
  // "constant", "sine", "chirp", "steps"; throws std::invalid_argument otherwise.
  static Signal parse(const std::string& name);

  // The signal's value at time t (s) since the script began.
  [[nodiscard]] double signal(double t) const noexcept;
  [[nodiscard]] Vector6 at(double t) const noexcept { return direction_ * signal(t); }
  // The instantaneous frequency at t (Hz): f for a sine, the sweep's for a chirp, 0 otherwise.
  [[nodiscard]] double frequency_at(double t) const noexcept;

 private:
  Signal signal_ = Signal::constant;
  Vector6 direction_ = Vector6::Zero();
  double start_s_ = 0.0, frequency_hz_ = 1.0, f0_ = 1.0, f1_ = 60.0, sweep_s_ = 10.0, step_s_ = 1.0;
  std::array<double, kMaxLevels> levels_{};
  int level_count_ = 0;
};

}  // namespace hapticd::models
