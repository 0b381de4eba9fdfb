#include "hapticd/teleop/rotation.hpp"

#include <cmath>

namespace hapticd::teleop {

Eigen::Vector3d rotation_vector(const Eigen::Quaterniond& q_in) noexcept {
  // q and -q are one rotation: take the one with w >= 0, whose angle is at most pi.
  const Eigen::Quaterniond q = q_in.w() < 0.0 ? Eigen::Quaterniond(-q_in.coeffs()) : q_in;
  const double s = q.vec().norm();
  if (s < 1e-12) return 2.0 * q.vec();  // sin(a/2) ~ a/2
  const double angle = 2.0 * std::atan2(s, q.w());
  return (angle / s) * q.vec();
}

Eigen::Quaterniond rotation_of(const Eigen::Vector3d& w) noexcept {
  const double angle = w.norm();
  if (angle < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized();
  const Eigen::Vector3d axis = w / angle;
  const double s = std::sin(0.5 * angle);
  return {std::cos(0.5 * angle), s * axis.x(), s * axis.y(), s * axis.z()};
}

}  // namespace hapticd::teleop
