#include "safety/thermal_limiter.hpp"

#include <algorithm>

namespace hapticd::server {

void ThermalLimiter::configure(const JointVector& peak, const JointVector& continuous, double time_constant_s,
                               double derate_from, double period_s) {
  peak_ = peak;
  continuous_ = continuous;
  for (int i = 0; i < continuous_.size(); ++i)
    if (!(continuous_[i] > 0.0) || continuous_[i] >= peak_[i]) continuous_[i] = peak_[i];
  load_.setZero(peak.size());
  limit_ = peak_;
  alpha_ = time_constant_s > 0.0 ? std::min(1.0, period_s / time_constant_s) : 0.0;
  derate_from_ = derate_from;
  derating_ = false;
}

void ThermalLimiter::update(const JointVector& torque) noexcept {
  if (alpha_ == 0.0) return;
  derating_ = false;
  for (int i = 0; i < load_.size(); ++i) {
    const double r = torque[i] / continuous_[i];
    load_[i] += alpha_ * (r * r - load_[i]);
    const double x = std::clamp((load_[i] - derate_from_) / (1.0 - derate_from_), 0.0, 1.0);
    limit_[i] = peak_[i] + x * (continuous_[i] - peak_[i]);
    derating_ = derating_ || x > 0.0;
  }
}

}  // namespace hapticd::server
