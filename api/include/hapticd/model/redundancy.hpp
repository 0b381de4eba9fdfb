#pragma once
// Redundancy resolution for an m x n task Jacobian (m <= 6 <= n <= 10, or any m <= n): generalised inverses,
// the null-space projector, and the velocity-, acceleration- and torque-level resolutions of
// docs/redundancy.md ([U06] methods 3). Real-time safe: fixed-capacity Eigen storage only.
//
// Every inverse is computed the same way: with the joint weighting W = L L^T (identity, a diagonal, or the
// joint-space inertia M), the singular value decomposition of A = J L^-T gives
//   J^W# = L^-T V diag(f(sigma)) U^T,
// with f(s) = 1/s above a tolerance and 0 below (the pseudoinverse: exact where J has full rank, minimising
// qd^T W qd), or f(s) = s / (s^2 + lambda^2) (the singularity-robust, damped inverse: bounded rates, inexact).
#include <Eigen/Cholesky>

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
  // damping: lambda [task units] (kDamped); tolerance: singular values below tolerance * sigma_max count as zero.
  void configure(InverseKind kind, int dof, const JointVector& weights, double damping = 0.0, double tolerance = 1e-9);

  // J^W# at this Jacobian; mass_llt: the Cholesky factor of M (used by kInertiaWeighted only). Real-time safe.
  void compute(const TaskJacobian& jacobian, const Eigen::LLT<JointMatrix>* mass_llt = nullptr) noexcept;

  [[nodiscard]] InverseKind kind() const noexcept { return kind_; }
  [[nodiscard]] const InverseJacobian& matrix() const noexcept { return inverse_; }
  // N = I - J^W# J: maps any joint vector into the null space (J N = 0 where J has full rank).
  [[nodiscard]] const JointMatrix& null_space_projector() const noexcept { return projector_; }
  // Singular values of A = J L^-T, largest first (for W = I those of J).
  [[nodiscard]] const TaskVector& singular_values() const noexcept { return singular_values_; }
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
  TaskJacobian scaled_;  // A = J L^-T
  InverseJacobian inverse_;
  JointMatrix projector_;
  TaskVector singular_values_;
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
