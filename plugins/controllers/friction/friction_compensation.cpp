#include "friction_compensation.hpp"

#include <algorithm>
#include <cmath>

namespace hapticd::controllers {

double FrictionCompensation::torque(int i, double velocity, double load_torque) const noexcept {
  const double direction = std::clamp(velocity / smooth_velocity_, -1.0, 1.0);
  return fraction_ * direction * models_[static_cast<std::size_t>(i)].magnitude(velocity, load_torque);
}

double FrictionCompensation::load_part(int i, double load_torque) const noexcept {
  const auto& a = models_[static_cast<std::size_t>(i)].load;
  const double l = std::abs(load_torque);
  return (a[2] * l + a[1]) * l + a[0];
}

}  // namespace hapticd::controllers
