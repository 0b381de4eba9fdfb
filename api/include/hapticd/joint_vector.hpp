#pragma once
#include <Eigen/Core>

namespace hapticd {

// Largest chain the SDK handles (ViSHaRD10). Joint-space quantities use fixed-capacity storage: the size is
// set once at configure time, and no heap memory is ever touched afterwards.
inline constexpr int kMaxJoints = 10;

using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxJoints, 1>;
using JointMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxJoints, kMaxJoints>;

// Joint positions [rad or m], velocities [rad/s or m/s] and efforts [N m or N] of a chain.
struct JointState {
  JointVector position;
  JointVector velocity;
  JointVector effort;

  void resize(int dof) {
    position.setZero(dof);
    velocity.setZero(dof);
    effort.setZero(dof);
  }
};

}  // namespace hapticd
