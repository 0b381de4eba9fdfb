#include "hapticd/model/output_capability.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <limits>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/position_solver.hpp"

namespace hapticd::model {
namespace {

using JointBy3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::ColMajor, kMaxJoints, 3>;

// Largest ball in {x : |rows_i x + offset_i| <= limit_i}: min_i (limit_i - |offset_i|) / |rows_i|.
WorstDirection inscribed_radius(const JointBy3& rows, const JointVector& offset, const JointVector& limit) {
  WorstDirection w;
  w.value = std::numeric_limits<double>::infinity();
  for (int i = 0; i < rows.rows(); ++i) {
    const double norm = rows.row(i).norm();
    if (norm < 1e-12) continue;  // this joint takes no part in the subspace
    const double r = std::max(0.0, limit[i] - std::abs(offset[i])) / norm;
    if (r < w.value) {
      w.value = r;
      w.direction = rows.row(i).transpose() / norm;
      w.limiting_joint = i;
    }
  }
  return w;
}

int subspace_column(const CapabilityOptions& o) {
  if (o.task == TaskRows::translation || o.task == TaskRows::rotation) return 0;
  return o.subspace == CapabilitySubspace::translation ? 0 : 3;
}

}  // namespace

PoseCapability output_capability(const RobotModel& model, ModelData& data, const JointVector& q, int frame_id,
                                 const CapabilityOptions& options) {
  return output_capability(model, data, q, frame_id, options, model.peak_torques(), model.speed_limits());
}

PoseCapability output_capability(const RobotModel& model, ModelData& data, const JointVector& q, int frame_id,
                                 const CapabilityOptions& options, const JointVector& torque_limits,
                                 const JointVector& speed_limits) {
  const int n = model.dof();
  forward_kinematics(model, data, q);
  joint_space_inertia(model, data);
  JointVector gravity = JointVector::Zero(n);
  if (options.include_gravity) {
    gravity_torques(model, data);
    gravity = data.gravity_torque;
  }
  TaskJacobian full;
  TaskJacobian j;
  frame_jacobian(model, data, frame_id, full);
  select_rows(full, options.task, j);
  const int col = subspace_column(options);
  const JointVector zero = JointVector::Zero(n);

  PoseCapability c;
  // Static force: tau = g + J^T w with w nonzero only in the subspace.
  const JointBy3 force_rows = j.transpose().middleCols<3>(col);
  c.force = inscribed_radius(force_rows, gravity, torque_limits);

  // Velocity and acceleration through the (minimum-norm) pseudoinverse of the task Jacobian.
  const Eigen::JacobiSVD<TaskJacobian> svd(j, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto& s = svd.singularValues();
  c.task_condition = s[s.size() - 1] > 0.0 ? s[0] / s[s.size() - 1] : std::numeric_limits<double>::infinity();
  if (s.size() < j.rows() || s[s.size() - 1] < 1e-9 * s[0]) {
    c.velocity = WorstDirection{};  // singular: some direction cannot be moved in
    c.acceleration = WorstDirection{};
    return c;
  }
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, 6> pinv =
      svd.matrixV() * s.cwiseInverse().asDiagonal() * svd.matrixU().transpose();
  const JointBy3 velocity_rows = pinv.middleCols<3>(col);
  c.velocity = inscribed_radius(velocity_rows, zero, speed_limits);
  const JointBy3 acceleration_rows = data.mass_matrix * velocity_rows;
  c.acceleration = inscribed_radius(acceleration_rows, gravity, torque_limits);
  return c;
}

GridCapability grid_output_capability(const RobotModel& model, int frame_id, const WorkspaceGrid& grid,
                                      const JointVector& q_seed, const CapabilityOptions& options) {
  ModelData data(model);
  GridCapability result;
  result.force.value = result.velocity.value = result.acceleration.value = std::numeric_limits<double>::infinity();
  PositionSolverOptions solver;
  solver.rows = grid.free_orientation ? TaskRows::translation : options.task;
  const int k = grid.points_per_axis;
  for (const Eigen::Vector3d& rpy : grid.orientation_offsets) {
    const Eigen::Matrix3d orientation =
        (Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()))
            .toRotationMatrix() *
        grid.nominal_orientation;
    JointVector q = q_seed;  // carried along the grid in serpentine order
    for (int a = 0; a < k; ++a) {
      for (int b0 = 0; b0 < k; ++b0) {
        const int b = (a % 2 == 0) ? b0 : k - 1 - b0;
        for (int c0 = 0; c0 < k; ++c0) {
          const int c = (b0 % 2 == 0) ? c0 : k - 1 - c0;
          const Eigen::Vector3d fraction(k > 1 ? double(a) / (k - 1) - 0.5 : 0.0,
                                         k > 1 ? double(b) / (k - 1) - 0.5 : 0.0,
                                         k > 1 ? double(c) / (k - 1) - 0.5 : 0.0);
          Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
          target.translation() = grid.center + grid.size.cwiseProduct(fraction);
          target.linear() = orientation;
          ++result.poses;
          JointVector trial = q;
          if (!solve_position(model, data, frame_id, target, trial, solver).converged) {
            trial = q_seed;  // retry from the nominal configuration
            if (!solve_position(model, data, frame_id, target, trial, solver).converged) continue;
          }
          q = trial;
          ++result.reached;
          const PoseCapability p = output_capability(model, data, q, frame_id, options);
          const auto keep_min = [&](WorstDirection& worst, Eigen::Vector3d& where, const WorstDirection& now) {
            if (now.value < worst.value) {
              worst = now;
              where = target.translation();
            }
          };
          keep_min(result.force, result.force_worst_position, p.force);
          keep_min(result.velocity, result.velocity_worst_position, p.velocity);
          keep_min(result.acceleration, result.acceleration_worst_position, p.acceleration);
          result.mean_force += p.force.value;
          result.mean_velocity += p.velocity.value;
          result.mean_acceleration += p.acceleration.value;
          result.worst_condition = std::max(result.worst_condition, p.task_condition);
        }
      }
    }
  }
  if (result.reached > 0) {
    result.mean_force /= result.reached;
    result.mean_velocity /= result.reached;
    result.mean_acceleration /= result.reached;
  }
  return result;
}

}  // namespace hapticd::model
