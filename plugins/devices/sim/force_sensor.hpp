#pragma once
// A six-axis force/torque sensor as the JR3 sensors of the ViSHaRD devices: first-order bandwidth (8 kHz),
// Gaussian noise (seeded), quantisation to 1/4000 of the range per axis, saturation at the range.
// Real-time safe.
#include <Eigen/Core>
#include <random>

namespace hapticd::sim {

using Vector6d = Eigen::Matrix<double, 6, 1>;

struct ForceSensorParameters {
  Vector6d range = (Vector6d() << 200, 200, 400, 12, 12, 12).finished();  // [N, N m]
  double resolution_fraction = 1.0 / 4000.0;
  double noise_lsb = 0.5;  // noise standard deviation in resolution steps
  double bandwidth_hz = 8000.0;
  bool quantise = true;
};

class ForceSensor {
 public:
  void configure(const ForceSensorParameters& p, std::uint64_t seed) {
    p_ = p;
    rng_.seed(seed);
    reset();
  }
  void reset() noexcept {
    filtered_.setZero();
    saturated_ = false;
  }
  // Advances the sensor's dynamics by dt under the true wrench (sensor frame, [force; torque]).
  void update(const Vector6d& wrench, double dt) noexcept {
    if (dt != alpha_dt_) {
      alpha_dt_ = dt;
      alpha_ = 1.0 - std::exp(-2.0 * M_PI * p_.bandwidth_hz * dt);
    }
    filtered_ += alpha_ * (wrench - filtered_);
  }
  // One reading: noise, quantisation and saturation on the filtered wrench.
  Vector6d read() noexcept {
    Vector6d out;
    saturated_ = false;
    for (int i = 0; i < 6; ++i) {
      const double lsb = p_.range[i] * p_.resolution_fraction;
      double v = filtered_[i] + p_.noise_lsb * lsb * noise_(rng_);
      if (p_.quantise) v = std::round(v / lsb) * lsb;
      if (std::abs(v) > p_.range[i]) {
        v = std::copysign(p_.range[i], v);
        saturated_ = true;
      }
      out[i] = v;
    }
    return out;
  }
  [[nodiscard]] bool saturated() const noexcept { return saturated_; }

 private:
  ForceSensorParameters p_;
  Vector6d filtered_ = Vector6d::Zero();
  bool saturated_ = false;
  double alpha_dt_ = -1.0;
  double alpha_ = 1.0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
};

// Encoder on the motor: the joint position as the controller sees it, in whole counts.
[[nodiscard]] inline double quantise_encoder(double joint_position, double counts_per_joint_rev) noexcept {
  if (counts_per_joint_rev <= 0.0) return joint_position;
  const double quantum = 2.0 * M_PI / counts_per_joint_rev;
  return std::floor(joint_position / quantum) * quantum;
}

}  // namespace hapticd::sim
