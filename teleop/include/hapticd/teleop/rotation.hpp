#pragma once
// Rotations as the teleoperation link uses them: a handle's orientation relative to where it was when the link
// started (world axes), the rotation vector between two orientations and its inverse. Real-time safe.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hapticd::teleop {

// The rotation vector (axis times angle, the shorter way round: |result| <= pi) of the unit quaternion q.
[[nodiscard]] Eigen::Vector3d rotation_vector(const Eigen::Quaterniond& q) noexcept;
// The unit quaternion of the rotation vector w.
[[nodiscard]] Eigen::Quaterniond rotation_of(const Eigen::Vector3d& w) noexcept;
// The rotation vector that turns `from` into `to` in world axes: rotation_of(result) * from = to.
[[nodiscard]] inline Eigen::Vector3d rotation_between(const Eigen::Quaterniond& from,
                                                      const Eigen::Quaterniond& to) noexcept {
  return rotation_vector(to * from.conjugate());
}

}  // namespace hapticd::teleop
