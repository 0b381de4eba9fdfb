#pragma once
// The in-loop half of the adaptive sliding-friction compensation ([U06] methods 1, [4.24]):
// every sample, per joint, the friction torque is estimated from the device's rigid-body model,
//   h_hat = tau + J^T F_h - (M qdd + C qd + g) - s(qd) f_load(t),
// with qd and qdd from backward differences of the positions over a window of N samples and tau, J^T F_h
// averaged over the same window. Samples above min_speed are mirrored to positive speed and accumulated into
// velocity bins (sum and count). Real-time safe; the bins are handed to the worker (FrictionRetuner) as a copy.
#include <array>

#include "friction_compensation.hpp"
#include "hapticd/joint_vector.hpp"

namespace hapticd::model {
struct ModelData;
}

namespace hapticd::controllers {

inline constexpr int kFrictionBins = 64;
inline constexpr int kMaxEstimationWindow = 64;

// Accumulated estimates per joint and velocity bin; bin b covers speeds [b, b + 1) * bin_width.
struct FrictionBinData {
  int dof = 0;
  double bin_width = 0.05;
  double time_s = 0.0;  // cycle time of the hand-over
  std::uint64_t sequence = 0;
  std::array<std::array<double, kFrictionBins>, kMaxJoints> sum{};        // sum of friction estimates [N m]
  std::array<std::array<double, kFrictionBins>, kMaxJoints> speed_sum{};  // sum of speeds [rad/s]
  std::array<std::array<double, kFrictionBins>, kMaxJoints> count{};

  void clear() noexcept {
    for (auto& a : sum) a.fill(0.0);
    for (auto& a : speed_sum) a.fill(0.0);
    for (auto& a : count) a.fill(0.0);
  }
};

class FrictionEstimator {
 public:
  void configure(int dof, double period_s, int window, double bin_width, double min_speed) noexcept;
  void reset(const JointVector& position) noexcept;
  // One sample: measured positions, the torque applied in the previous cycle, J^T F_h, the cycle's model
  // terms and the compensator's present models (for the load part).
  // record = false computes the estimate without adding it to the bins.
  void sample(const JointVector& position, const JointVector& applied_torque, const JointVector& operator_torques,
              const model::ModelData& data, const FrictionCompensation& friction, bool record = true) noexcept;
  [[nodiscard]] FrictionBinData& bins() noexcept { return bins_; }
  // The last estimate per joint (0 below min_speed, and with the present load part removed), its velocity
  // and the static load torque t = g - J^T F_h; valid() once the window has filled.
  [[nodiscard]] const JointVector& last_estimate() const noexcept { return estimate_; }
  [[nodiscard]] const JointVector& last_velocity() const noexcept { return velocity_; }
  [[nodiscard]] const JointVector& last_load() const noexcept { return load_; }
  [[nodiscard]] bool valid() const noexcept { return filled_ >= 2 * window_; }

 private:
  int dof_ = 0, window_ = 40, filled_ = 0, head_ = 0, torque_head_ = 0;
  double period_s_ = 5e-4, min_speed_ = 0.05;
  // Ring of the last 2N+1 positions and of the last N torques (applied and operator).
  std::array<JointVector, 2 * kMaxEstimationWindow + 1> positions_{};
  std::array<JointVector, kMaxEstimationWindow> torques_{};
  JointVector torque_sum_, velocity_, acceleration_, estimate_, dynamics_, load_;
  FrictionBinData bins_;
};

}  // namespace hapticd::controllers
