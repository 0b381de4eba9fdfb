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
