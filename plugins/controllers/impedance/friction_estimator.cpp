#include "friction_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "hapticd/model/model_data.hpp"

namespace hapticd::controllers {

void FrictionEstimator::configure(int dof, double period_s, int window, double bin_width, double min_speed) noexcept {
  dof_ = dof;
  period_s_ = period_s;
  window_ = std::clamp(window, 2, kMaxEstimationWindow);
  min_speed_ = min_speed;
  bins_.dof = dof;
  bins_.bin_width = bin_width;
  for (auto& p : positions_) p.setZero(dof);
  for (auto& t : torques_) t.setZero(dof);
  torque_sum_.setZero(dof);
  velocity_.setZero(dof);
  acceleration_.setZero(dof);
  estimate_.setZero(dof);
  dynamics_.setZero(dof);
  load_.setZero(dof);
}

void FrictionEstimator::reset(const JointVector& position) noexcept {
  for (auto& p : positions_) p = position;
  for (auto& t : torques_) t.setZero(dof_);
  torque_sum_.setZero(dof_);
  filled_ = 0;
  head_ = 0;
  torque_head_ = 0;
  estimate_.setZero(dof_);
  bins_.clear();
}

void FrictionEstimator::sample(const JointVector& position, const JointVector& applied_torque,
                               const JointVector& operator_torques, const model::ModelData& d,
                               const FrictionCompensation& friction, bool record) noexcept {
  constexpr int kRing = 2 * kMaxEstimationWindow + 1;
  const int n = window_;
  head_ = (head_ + 1) % kRing;
  positions_[static_cast<std::size_t>(head_)] = position;
  torque_head_ = (torque_head_ + 1) % n;
  const int torque_slot = torque_head_;
  torque_sum_ += applied_torque + operator_torques - torques_[static_cast<std::size_t>(torque_slot)];
  torques_[static_cast<std::size_t>(torque_slot)] = applied_torque + operator_torques;
  if (torque_slot == 0) {  // re-sum once per window against rounding drift
    torque_sum_.setZero(dof_);
    for (int k = 0; k < n; ++k) torque_sum_ += torques_[static_cast<std::size_t>(k)];
  }
  if (filled_ < 2 * n) {
    ++filled_;
    estimate_.setZero(dof_);
    return;
  }
  const JointVector& q0 = positions_[static_cast<std::size_t>((head_ - n + kRing) % kRing)];
  const JointVector& q00 = positions_[static_cast<std::size_t>((head_ - 2 * n + kRing) % kRing)];
  const double span = n * period_s_;
  velocity_ = (position - q0) / span;
  acceleration_ = (velocity_ - (q0 - q00) / span) / span;
  dynamics_.noalias() = d.mass_matrix * acceleration_;
  dynamics_ += d.coriolis_torque + d.gravity_torque;
  load_ = d.gravity_torque - operator_torques;
  for (int i = 0; i < dof_; ++i) {
    const double v = velocity_[i];
    const double speed = std::abs(v);
    if (speed < min_speed_) {
      estimate_[i] = 0.0;
      continue;
    }
    const double sign = v > 0.0 ? 1.0 : -1.0;
    const double load = load_[i];
    const double h = torque_sum_[i] / n - dynamics_[i] - sign * friction.load_part(i, load);
    estimate_[i] = h;
    if (!record) continue;
    const int bin = static_cast<int>(speed / bins_.bin_width);
    if (bin >= kFrictionBins) continue;
    const auto j = static_cast<std::size_t>(i);
    const auto b = static_cast<std::size_t>(bin);
    bins_.sum[j][b] += sign * h;  // mirrored: friction magnitude in the direction of motion
    bins_.speed_sum[j][b] += speed;
    bins_.count[j][b] += 1.0;
  }
}

}  // namespace hapticd::controllers
