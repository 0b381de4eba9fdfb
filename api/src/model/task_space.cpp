#include "hapticd/model/task_space.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <cmath>
#include <limits>

namespace hapticd::model {

void select_rows(const TaskJacobian& full, TaskRows rows, TaskJacobian& task) noexcept {
  switch (rows) {
    case TaskRows::full:
      task = full;
      break;
    case TaskRows::translation:
      task = full.topRows(3);
      break;
    case TaskRows::rotation:
      task = full.bottomRows(3);
      break;
  }
}

bool operational_space_inertia(const ModelData& data, const TaskJacobian& jacobian, TaskMatrix& lambda) noexcept {
  // J M^-1 J^T = (L^-1 J^T)^T (L^-1 J^T) with M = L L^T.
  using Transposed = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxJoints, 6>;
  Transposed x = jacobian.transpose();
  data.mass_llt.matrixL().solveInPlace(x);
  const TaskMatrix inverse = x.transpose() * x;
  Eigen::LDLT<TaskMatrix> ldlt(inverse);
  const double largest = inverse.diagonal().cwiseAbs().maxCoeff();
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * largest)) return false;
  lambda.setIdentity(inverse.rows(), inverse.cols());
  ldlt.solveInPlace(lambda);
  return true;
}

JointVector minimum_norm_solution(const TaskJacobian& jacobian, const TaskVector& v, double damping) noexcept {
  TaskMatrix jjt = jacobian * jacobian.transpose();
  jjt.diagonal().array() += damping;
  const TaskVector weights = jjt.ldlt().solve(v);
  JointVector q = JointVector::Zero(jacobian.cols());
  q.noalias() = jacobian.transpose() * weights;
  return q;
}

JointVector jacobian_transpose_times(const TaskJacobian& jacobian, int rows, const Vector6d& wrench) noexcept {
  JointVector tau = JointVector::Zero(jacobian.cols());
  for (int i = 0; i < jacobian.cols(); ++i) {
    double sum = 0.0;
    for (int r = 0; r < rows; ++r) sum += jacobian(r, i) * wrench[r];
    tau[i] = sum;
  }
  return tau;
}

void declare_task_parameter(ParameterSchema& schema, const std::string& description) {
  schema.string("task", description + ": auto (translation below 6 joints), translation, or full (6-D)")
      .choices({"auto", "translation", "full"})
      .default_value(std::string("auto"));
}

int task_rows(const std::string& choice, int dof) {
  const int rows = choice == "full" ? 6 : choice == "translation" ? 3 : (dof >= 6 ? 6 : 3);
  if (rows > dof) {
    throw ParameterError("task", "a 6-D task needs at least 6 joints; this device has " + std::to_string(dof));
  }
  return rows;
}

JointVector operator_wrench_torques(const ChainState& chain, int rows) noexcept {
  if (!chain.has_operator_wrench)
    return JointVector::Zero(chain.model != nullptr ? chain.data->frame_jacobian.cols() : 0);
  Vector6d wrench;
  wrench << chain.operator_wrench.force, chain.operator_wrench.torque;
  return jacobian_transpose_times(chain.data->frame_jacobian, rows, wrench);
}

double manipulability(const TaskJacobian& jacobian) noexcept {
  const TaskMatrix jjt = jacobian * jacobian.transpose();
  const double det = jjt.determinant();
  return det > 0.0 ? std::sqrt(det) : 0.0;
}

double condition_number(const TaskJacobian& jacobian) noexcept {
  const Eigen::JacobiSVD<TaskJacobian> svd(jacobian);
  const auto& s = svd.singularValues();
  const double smallest = s[s.size() - 1];
  if (!(smallest > 0.0)) return std::numeric_limits<double>::infinity();
  return s[0] / smallest;
}

}  // namespace hapticd::model
