#pragma once
// Kinematics of a RobotModel: forward kinematics of any frame, geometric and analytic Jacobians, dJ/dt qd.
// Every function is real-time safe (no allocation, no exceptions) once ModelData exists. Jacobians are
// 6 x n with rows [linear; angular] in world axes, reference point at the frame origin.
#include <Eigen/Geometry>

#include "hapticd/export.hpp"
#include "hapticd/model/model_data.hpp"

namespace hapticd::model {

// Whether forward_kinematics also turns every body's inertia into the world frame (what the dynamics need;
// kinematics alone - inverse kinematics, side criteria - skip it and save about a third of the time).
enum class BodyInertias { update, skip };

// Poses and motion subspaces of every body at q (and their world inertias unless skipped).
HAPTICD_API void forward_kinematics(const RobotModel& model, ModelData& data, const JointVector& q,
                                    BodyInertias inertias = BodyInertias::update) noexcept;
// forward_kinematics plus body velocities, dS/dt and bias accelerations at (q, qd).
HAPTICD_API void forward_velocity(const RobotModel& model, ModelData& data, const JointVector& q, const JointVector& qd,
                                  BodyInertias inertias = BodyInertias::update) noexcept;

// World pose of a frame. Requires forward_kinematics.
[[nodiscard]] HAPTICD_API Eigen::Isometry3d frame_pose(const RobotModel& model, const ModelData& data,
                                                       int frame_id) noexcept;
// Geometric Jacobian of a frame (6 x n). Requires forward_kinematics.
HAPTICD_API void frame_jacobian(const RobotModel& model, const ModelData& data, int frame_id,
                                TaskJacobian& jacobian) noexcept;
// dJ/dt qd of a frame: the frame origin's classical linear and the angular acceleration for qdd = 0.
// Requires forward_velocity.
[[nodiscard]] HAPTICD_API Vector6d frame_jacobian_dot_times_qd(const RobotModel& model, const ModelData& data,
                                                               int frame_id) noexcept;
// World-frame twist [linear; angular] of a frame. Requires forward_velocity.
[[nodiscard]] HAPTICD_API Vector6d frame_velocity(const RobotModel& model, const ModelData& data,
                                                  int frame_id) noexcept;

// Pose difference a - b as [position difference; rotation vector of a b^T] (world axes): the error a
// Newton step on the Jacobian corrects.
[[nodiscard]] HAPTICD_API Vector6d pose_difference(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) noexcept;

// Roll-pitch-yaw angles (URDF convention R = Rz(yaw) Ry(pitch) Rx(roll)), pitch in [-pi/2, pi/2].
[[nodiscard]] HAPTICD_API Eigen::Vector3d roll_pitch_yaw(const Eigen::Matrix3d& rotation) noexcept;
// Analytic Jacobian: rows [linear; d(roll, pitch, yaw)/dt] from the geometric Jacobian at a frame rotation.
// Returns false (and leaves `analytic` unspecified) within `min_cos_pitch` of the representation
// singularity cos(pitch) = 0.
HAPTICD_API bool analytic_jacobian(const TaskJacobian& geometric, const Eigen::Matrix3d& rotation,
                                   TaskJacobian& analytic, double min_cos_pitch = 1e-6) noexcept;

}  // namespace hapticd::model
