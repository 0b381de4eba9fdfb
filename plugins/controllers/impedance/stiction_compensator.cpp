#include "stiction_compensator.hpp"

#include <algorithm>
#include <cmath>

namespace hapticd::controllers {

void StictionCompensator::configure(int dof, const StictionSettings& settings, double period_s) noexcept {
  dof_ = dof;
  s_ = settings;
  period_s_ = period_s;
  reset();
}

void StictionCompensator::reset() noexcept {
  moving_.fill(false);
  held_.fill(0.0);
  integral_.fill(0.0);
  last_sliding_.fill(0.0);
}

void StictionCompensator::update(const JointVector& velocity, const JointVector& sliding,
                                 const JointVector& projected_error, JointVector& out) noexcept {
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double speed = std::abs(velocity[i]);
    if (!moving_[k] && speed > s_.moving_velocity) {
      moving_[k] = true;
    } else if (moving_[k] && speed < s_.rest_velocity) {
      moving_[k] = false;
      held_[k] = last_sliding_[k];  // h_i at the switching instant: no jump
      integral_[k] = 0.0;
    }
    if (moving_[k]) {
      last_sliding_[k] = sliding[i];
      out[i] = sliding[i];
    } else {
      integral_[k] = std::clamp(integral_[k] + period_s_ * s_.integral_gain * projected_error[i],
                                -s_.integrator_limit_nm, s_.integrator_limit_nm);
      out[i] = held_[k] + integral_[k];
    }
  }
}

}  // namespace hapticd::controllers
