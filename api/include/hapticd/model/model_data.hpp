#pragma once
// The per-loop workspace of the model algorithms: sized once from a RobotModel, then every algorithm writes
// into it without touching the heap. One ModelData per thread; the RobotModel is shared.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <array>

#include "hapticd/export.hpp"
#include "hapticd/joint_vector.hpp"
#include "hapticd/model/robot_model.hpp"
#include "hapticd/model/spatial_algebra.hpp"

namespace hapticd::model {

using Vector6d = Eigen::Matrix<double, 6, 1>;
// Task-space Jacobians and matrices: up to 6 rows ([linear; angular] for a full frame Jacobian).
using TaskJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxJoints>;
using TaskMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 6, 6>;
using TaskVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 6, 1>;

struct HAPTICD_API ModelData {
  explicit ModelData(const RobotModel& model);

  int dof = 0;
  JointVector q;   // configuration of the last forward_kinematics
  JointVector qd;  // velocity of the last forward_velocity

  // Per body i (the body moved by joint i), world frame:
  std::array<Eigen::Matrix3d, kMaxJoints> rotation{};  // orientation of the joint frame
  std::array<Eigen::Vector3d, kMaxJoints> position{};  // origin of the joint frame
  std::array<Motion, kMaxJoints> motion_subspace{};    // S_i: joint i's unit motion
  std::array<SpatialInertia, kMaxJoints> inertia{};    // body inertia
  std::array<SpatialInertia, kMaxJoints> composite{};  // inertia of bodies i..n-1
  std::array<Motion, kMaxJoints> velocity{};           // v_i
  std::array<Motion, kMaxJoints> subspace_rate{};      // dS_i/dt = v_i x S_i
  std::array<Motion, kMaxJoints> bias_acceleration{};  // a_i with qdd = 0 and no gravity
  std::array<Force, kMaxJoints> force{};               // RNEA scratch
  std::array<Force, kMaxJoints> composite_subspace{};  // CRBA scratch: composite_i * S_i

  // Outputs.
  JointMatrix mass_matrix;           // M(q), reflected drive inertia included
  Eigen::LLT<JointMatrix> mass_llt;  // Cholesky factor of mass_matrix (after joint_space_inertia)
  JointVector gravity_torque;        // g(q)
  JointVector coriolis_torque;       // C(q, qd) qd
  JointVector scratch;               // joint-space scratch vector

  // The frame chosen in compute_cycle_terms:
  Eigen::Isometry3d frame_pose = Eigen::Isometry3d::Identity();
  TaskJacobian frame_jacobian;  // 6 x n, rows [linear; angular]
  Vector6d frame_jacobian_dot_qd = Vector6d::Zero();
};

}  // namespace hapticd::model
