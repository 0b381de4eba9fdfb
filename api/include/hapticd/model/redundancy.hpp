#pragma once
// Redundancy resolution for an m x n task Jacobian (m <= 6 <= n <= 10, or any m <= n): generalised inverses,
// the null-space projector, and the velocity-, acceleration- and torque-level resolutions of
// docs/redundancy.md ([U06] methods 3). Real-time safe: fixed-capacity Eigen storage only.
//
// Every inverse is computed the same way, without a singular value decomposition: with the joint weighting
// W = L L^T (identity, a diagonal, or the joint-space inertia M, whose Cholesky factor the model terms already
// hold) and A = J L^-T, the m x m Gram matrix G = A A^T = J W^-1 J^T gives
//   J^W# = L^-T A^T (G + lambda^2 I)^-1
// by one Cholesky factorisation of G: lambda = 0 is the exact inverse where J has full row rank (minimising
// qd^T W qd), lambda > 0 the singularity-robust, damped inverse (bounded rates, inexact). Where G is singular to
// working precision (a pivot below 1e-13 of the largest: sigma_min / sigma_max below about 3e-7), the exact
// kinds fall back to G's eigen-decomposition G = U S^2 U^T and drop the lost directions:
//   J^W# = L^-T A^T U diag(1/s^2 above the tolerance, else 0) U^T.
// This is the SVD's f(s) = 1/s, or s / (s^2 + lambda^2), written as A^T U diag(f(s)/s) U^T.
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "hapticd/export.hpp"
#include "hapticd/model/model_data.hpp"

namespace hapticd::model {

// n x m: a generalised inverse of a task Jacobian.
using InverseJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxJoints, 6>;

enum class InverseKind {
  pseudoinverse,     // W = I (SVD)
  weighted,          // W = diag(weights)
  damped,            // singularity-robust: W = diag(weights), damped singular values
  inertia_weighted,  // W = M: the dynamically consistent inverse
};

[[nodiscard]] HAPTICD_API const char* to_string(InverseKind kind) noexcept;

class HAPTICD_API GeneralizedInverse {
 public:
  // Before use (not real-time safe: sizes the workspace). weights: n positive entries (kWeighted, kDamped);
  // damping: lambda [task units] (kDamped); tolerance: singular values below tolerance * sigma_max count as zero
  // (effectively at least 3e-7: below that the Gram matrix cannot tell them from zero).
  void configure(InverseKind kind, int dof, const JointVector& weights, double damping = 0.0, double tolerance = 1e-9);

  // J^W# at this Jacobian; mass_llt: the Cholesky factor of M (used by kInertiaWeighted only). Real-time safe.
  void compute(const TaskJacobian& jacobian, const Eigen::LLT<JointMatrix>* mass_llt = nullptr) noexcept;

  [[nodiscard]] InverseKind kind() const noexcept { return kind_; }
  [[nodiscard]] const InverseJacobian& matrix() const noexcept { return inverse_; }
  // N = I - J^W# J: maps any joint vector into the null space (J N = 0 where J has full rank). Formed on demand
  // (n x n); project_null_space applies it without forming it.
  [[nodiscard]] JointMatrix null_space_projector() const noexcept;
  [[nodiscard]] JointVector project_null_space(const JointVector& v) const noexcept;
  // Task rows the inverse treats as independent (m unless the exact kinds dropped lost directions).
  [[nodiscard]] int rank() const noexcept { return rank_; }

  // x -> J^W# x (m entries) and the W^-1 weighting of a gradient (the homogeneous solution must descend along
  // W^-1 grad H to still extremise H).
  [[nodiscard]] JointVector solve(const TaskVector& x) const noexcept;
  [[nodiscard]] JointVector weight_inverse_times(const JointVector& v) const noexcept;

 private:
  InverseKind kind_ = InverseKind::pseudoinverse;
  int dof_ = 0;
  double damping_ = 0.0, tolerance_ = 1e-9;
  JointVector weights_;       // diagonal W (kWeighted, kDamped)
  JointVector inverse_sqrt_;  // diag(1 / sqrt(w))
  const Eigen::LLT<JointMatrix>* mass_llt_ = nullptr;
  TaskJacobian jacobian_;     // J of the last compute
  InverseJacobian scaled_t_;  // A^T = L^-1 J^T
  TaskMatrix gram_;           // G = A A^T (+ lambda^2 I)
  TaskMatrix gram_inverse_;   // its (truncated) inverse
  Eigen::LLT<TaskMatrix> gram_llt_;
  Eigen::SelfAdjointEigenSolver<TaskMatrix> gram_eigen_;  // the rank-deficient fallback
  InverseJacobian inverse_;
  int rank_ = 0;
};

// Velocity level: qd = J^W# xd + N qd0.
[[nodiscard]] HAPTICD_API JointVector resolve_velocity(const GeneralizedInverse& inverse, const TaskVector& xd,
                                                       const JointVector& qd0) noexcept;
// Acceleration level: qdd = J^W# (xdd - Jd qd) + N qdd0; xdd_minus_bias = xdd - Jd qd.
[[nodiscard]] HAPTICD_API JointVector resolve_acceleration(const GeneralizedInverse& inverse,
                                                           const TaskVector& xdd_minus_bias,
                                                           const JointVector& qdd0) noexcept;
// Torque level: (I - J^T J^{M#T}) tau0, the dynamically consistent null-space torque: it produces no task
// acceleration. inertia_weighted must be a kInertiaWeighted inverse computed at the same J.
[[nodiscard]] HAPTICD_API JointVector null_space_torque(const GeneralizedInverse& inertia_weighted,
                                                        const TaskJacobian& jacobian, const JointVector& tau0) noexcept;

}  // namespace hapticd::model
