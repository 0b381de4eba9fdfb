#include "hapticd/model/position_solver.hpp"

#include <Eigen/Cholesky>

#include "hapticd/model/kinematics.hpp"

namespace hapticd::model {
namespace {

TaskVector select(const Vector6d& e, TaskRows rows) {
  switch (rows) {
    case TaskRows::translation:
      return e.head<3>();
    case TaskRows::rotation:
      return e.tail<3>();
    case TaskRows::full:
      break;
  }
  return e;
}

}  // namespace

PositionSolution solve_position(const RobotModel& model, ModelData& data, int frame_id, const Eigen::Isometry3d& target,
                                JointVector& q, const PositionSolverOptions& options) noexcept {
  PositionSolution result;
  TaskJacobian full;
  TaskJacobian j;
  for (result.iterations = 0; result.iterations <= options.max_iterations; ++result.iterations) {
    forward_kinematics(model, data, q);
    const TaskVector e = select(pose_difference(target, frame_pose(model, data, frame_id)), options.rows);
    result.error = e.norm();
    if (result.error < options.tolerance) {
      result.converged = true;
      return result;
    }
    if (result.iterations == options.max_iterations) break;
    frame_jacobian(model, data, frame_id, full);
    select_rows(full, options.rows, j);
    TaskMatrix jjt = j * j.transpose();
    jjt.diagonal().array() += options.damping;
    const TaskVector weights = jjt.ldlt().solve(e);
    JointVector step = JointVector::Zero(q.size());
    step.noalias() = j.transpose() * weights;
    const double largest = step.cwiseAbs().maxCoeff();
    if (largest > options.max_step) step *= options.max_step / largest;
    q += step;
  }
  return result;
}

}  // namespace hapticd::model
