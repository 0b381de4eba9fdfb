#include "hapticd/model/redundancy.hpp"

#include <algorithm>
#include <cmath>

#include "triangular_solve.hpp"

namespace hapticd::model {

const char* to_string(InverseKind kind) noexcept {
  switch (kind) {
    case InverseKind::pseudoinverse:
      return "pseudoinverse";
    case InverseKind::weighted:
      return "weighted";
    case InverseKind::damped:
      return "damped";
    case InverseKind::inertia_weighted:
      return "inertia_weighted";
  }
  return "?";
}

void GeneralizedInverse::configure(InverseKind kind, int dof, const JointVector& weights, double damping,
                                   double tolerance) {
  kind_ = kind;
  dof_ = dof;
  damping_ = damping;
  tolerance_ = tolerance;
  weights_ = weights.size() == dof ? weights : JointVector(JointVector::Ones(dof));
  if (kind == InverseKind::pseudoinverse) weights_.setOnes(dof);
  inverse_sqrt_ = weights_.cwiseSqrt().cwiseInverse();
  jacobian_.setZero(6, dof);
  scaled_t_.setZero(dof, 6);
  gram_.setZero(6, 6);
  gram_inverse_.setZero(6, 6);
  inverse_.setZero(dof, 6);
  rank_ = 0;
}

void GeneralizedInverse::compute(const TaskJacobian& jacobian, const Eigen::LLT<JointMatrix>* mass_llt) noexcept {
  const auto m = jacobian.rows();
  const auto n = jacobian.cols();
  mass_llt_ = kind_ == InverseKind::inertia_weighted ? mass_llt : nullptr;
  jacobian_ = jacobian;
  // A^T = L^-1 J^T: for a diagonal W the rows of J^T scaled by 1/sqrt(w); for W = M = L L^T a triangular solve.
  if (mass_llt_ != nullptr) {
    scaled_t_ = jacobian.transpose();
    detail::solve_lower_in_place(mass_llt_->matrixLLT(), scaled_t_);
  } else {
    scaled_t_.noalias() = inverse_sqrt_.head(n).asDiagonal() * jacobian.transpose();
  }
  // Small products coefficient-wise (lazyProduct): Eigen's blocked GEMM costs more than it saves at 6 x 10.
  gram_.noalias() = scaled_t_.transpose().lazyProduct(scaled_t_);
  if (kind_ == InverseKind::damped) gram_.diagonal().array() += damping_ * damping_;
  gram_llt_.compute(gram_);
  // A pivot below 1e-13 of the largest: G is singular to working precision (sigma ratio below about 3e-7).
  constexpr double kSingularPivot = 1e-13;
  const auto pivots = gram_llt_.matrixLLT().diagonal().cwiseAbs2();
  const bool factored =
      gram_llt_.info() == Eigen::Success && m > 0 && pivots.minCoeff() > kSingularPivot * pivots.maxCoeff();
  if (factored || (kind_ == InverseKind::damped && gram_llt_.info() == Eigen::Success)) {
    gram_inverse_.setIdentity(m, m);
    detail::cholesky_solve_in_place(gram_llt_.matrixLLT(), gram_inverse_);
    rank_ = static_cast<int>(m);
  } else {
    // Eigenvalues of G are the squared singular values of A; drop those below the tolerance.
    gram_eigen_.compute(gram_);
    const auto& s2 = gram_eigen_.eigenvalues();  // ascending
    const double largest = m > 0 ? std::max(s2[m - 1], 0.0) : 0.0;
    const double floor = std::max(tolerance_ * tolerance_, kSingularPivot) * largest;
    TaskVector f = TaskVector::Zero(m);
    rank_ = 0;
    for (Eigen::Index i = 0; i < m; ++i) {
      if (s2[i] > floor && s2[i] > 0.0) {
        f[i] = 1.0 / s2[i];
        ++rank_;
      }
    }
    gram_inverse_.noalias() = gram_eigen_.eigenvectors() * f.asDiagonal() * gram_eigen_.eigenvectors().transpose();
  }
  inverse_.noalias() = scaled_t_.lazyProduct(gram_inverse_);
  // J^W# = L^-T A^T G^-1.
  if (mass_llt_ != nullptr) {
    detail::solve_upper_in_place(mass_llt_->matrixLLT(), inverse_);
  } else {
    inverse_ = inverse_sqrt_.head(n).asDiagonal() * inverse_;
  }
}

JointMatrix GeneralizedInverse::null_space_projector() const noexcept {
  JointMatrix projector = JointMatrix::Identity(jacobian_.cols(), jacobian_.cols());
  projector.noalias() -= inverse_ * jacobian_;
  return projector;
}

JointVector GeneralizedInverse::project_null_space(const JointVector& v) const noexcept {
  // (I - J^W# J) v = v - J^W# (J v).
  TaskVector x(jacobian_.rows());
  x.noalias() = jacobian_ * v;
  JointVector out = v;
  out.noalias() -= inverse_ * x;
  return out;
}

JointVector GeneralizedInverse::solve(const TaskVector& x) const noexcept {
  JointVector q(inverse_.rows());
  q.noalias() = inverse_ * x;
  return q;
}

JointVector GeneralizedInverse::weight_inverse_times(const JointVector& v) const noexcept {
  if (mass_llt_ != nullptr) return mass_llt_->solve(v);
  return weights_.head(v.size()).cwiseInverse().cwiseProduct(v);
}

JointVector resolve_velocity(const GeneralizedInverse& inverse, const TaskVector& xd, const JointVector& qd0) noexcept {
  JointVector qd = inverse.solve(xd);
  qd += inverse.project_null_space(qd0);
  return qd;
}

JointVector resolve_acceleration(const GeneralizedInverse& inverse, const TaskVector& xdd_minus_bias,
                                 const JointVector& qdd0) noexcept {
  return resolve_velocity(inverse, xdd_minus_bias, qdd0);  // the same algebra one derivative up
}

JointVector null_space_torque(const GeneralizedInverse& inertia_weighted, const TaskJacobian& jacobian,
                              const JointVector& tau0) noexcept {
  // (I - J^T J^{M#T}) tau0 = tau0 - J^T (J^{M#T} tau0).
  TaskVector f(jacobian.rows());
  f.noalias() = inertia_weighted.matrix().transpose() * tau0;
  JointVector tau = tau0;
  tau.noalias() -= jacobian.transpose() * f;
  return tau;
}

}  // namespace hapticd::model
