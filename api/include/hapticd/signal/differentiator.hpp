#pragma once
// Velocity from sampled positions, as controllers must do on the devices (encoders, no tachometers): backward
// difference followed by a first-order low-pass at fc. Real-time safe after reset().
#include <cmath>

namespace hapticd::signal {

template <typename Vector>
class Differentiator {
 public:
  // period: sample period [s]; cutoff_hz: low-pass of the difference (<= 0: none).
  void configure(double period, double cutoff_hz) noexcept {
    period_ = period;
    alpha_ = cutoff_hz > 0.0 ? 1.0 - std::exp(-2.0 * M_PI * cutoff_hz * period) : 1.0;
  }
  void reset(const Vector& position) noexcept {
    previous_ = position;
    velocity_ = position * 0.0;
  }
  const Vector& update(const Vector& position) noexcept { return update(position, period_); }
  // The same after `elapsed` seconds instead of one period (a loop that skipped periods): the difference is
  // taken over the time that really passed, so a late sample is not mistaken for a fast motion.
  const Vector& update(const Vector& position, double elapsed) noexcept {
    velocity_ += alpha_ * ((position - previous_) / elapsed - velocity_);
    previous_ = position;
    return velocity_;
  }
  [[nodiscard]] const Vector& value() const noexcept { return velocity_; }

 private:
  double period_ = 1.0;
  double alpha_ = 1.0;
  Vector previous_, velocity_;
};

// First-order low-pass at cutoff_hz (<= 0: none, the output is the input). Real-time safe after reset().
template <typename Vector>
class LowPass {
 public:
  void configure(double period, double cutoff_hz) noexcept {
    alpha_ = cutoff_hz > 0.0 ? 1.0 - std::exp(-2.0 * M_PI * cutoff_hz * period) : 1.0;
  }
  void reset(const Vector& value) noexcept { value_ = value; }
  const Vector& update(const Vector& input) noexcept {
    value_ += alpha_ * (input - value_);
    return value_;
  }
  [[nodiscard]] const Vector& value() const noexcept { return value_; }

 private:
  double alpha_ = 1.0;
  Vector value_;
};

// Rate limiter: the output follows the input with at most max_rate per second in each element.
template <typename Vector>
class RateLimiter {
 public:
  void configure(double period, double max_rate) noexcept { step_ = period * max_rate; }
  void reset(const Vector& value) noexcept { value_ = value; }
  const Vector& update(const Vector& target) noexcept {
    value_ += (target - value_).cwiseMax(-step_).cwiseMin(step_);
    return value_;
  }
  [[nodiscard]] const Vector& value() const noexcept { return value_; }

 private:
  double step_ = 0.0;
  Vector value_;
};

}  // namespace hapticd::signal
