#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hapticd {

// Pose of a frame in the world (or a stated reference) frame: position [m], orientation as a unit quaternion
// (no representation singularities).
struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// The same pose as a rigid transform, and back.
[[nodiscard]] inline Eigen::Isometry3d to_isometry(const Pose& pose) {
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.linear() = pose.orientation.normalized().toRotationMatrix();
  x.translation() = pose.position;
  return x;
}
[[nodiscard]] inline Pose to_pose(const Eigen::Isometry3d& x) {
  return Pose{x.translation(), Eigen::Quaterniond(x.linear())};
}

// Linear [m/s] and angular [rad/s] velocity; also used for accelerations [m/s^2, rad/s^2].
struct Twist {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};

// Force [N] and torque [N m]. Sign convention of the whole code base (docs/conventions.md): a measured
// operator wrench is the wrench the operator applies TO the handle.
struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
};

}  // namespace hapticd
