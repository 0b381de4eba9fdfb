#pragma once
// Numerical inverse position kinematics (damped least squares Newton iterations) for off-line tools such as
// the output-capability analysis: find q that puts a frame at a target pose, starting from a seed. For the
// real-time inverse kinematics plugins see plugins/ik (redundancy resolution lives there).
#include <Eigen/Geometry>

#include "hapticd/export.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/task_space.hpp"

namespace hapticd::model {

struct PositionSolverOptions {
  TaskRows rows = TaskRows::full;  // kTranslation: position only (orientation free)
  int max_iterations = 200;
  double tolerance = 1e-10;  // on the position [m] and orientation [rad] error norm
  double damping = 1e-6;     // Levenberg-Marquardt damping of J J^T
  double max_step = 0.2;     // largest joint step per iteration [rad or m]
};

struct PositionSolution {
  bool converged = false;
  int iterations = 0;
  double error = 0.0;  // final error norm
};

// On entry q is the seed; on exit the solution (also when not converged: the best iterate).
HAPTICD_API PositionSolution solve_position(const RobotModel& model, ModelData& data, int frame_id,
                                            const Eigen::Isometry3d& target, JointVector& q,
                                            const PositionSolverOptions& options = {}) noexcept;

}  // namespace hapticd::model
