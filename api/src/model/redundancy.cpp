#include "hapticd/model/redundancy.hpp"

#include <Eigen/SVD>
#include <cmath>

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
  inverse_.setZero(dof, 6);
  projector_.setIdentity(dof, dof);
  scaled_.setZero(6, dof);
  singular_values_.setZero(6);
}

void GeneralizedInverse::compute(const TaskJacobian& jacobian, const Eigen::LLT<JointMatrix>* mass_llt) noexcept {
  const auto m = jacobian.rows();
  const auto n = jacobian.cols();
  mass_llt_ = kind_ == InverseKind::inertia_weighted ? mass_llt : nullptr;
  // A = J L^-T: for a diagonal W, the columns scaled by 1/sqrt(w); for W = M = L L^T, (L^-1 J^T)^T.
  if (mass_llt_ != nullptr) {
    InverseJacobian t = jacobian.transpose();
    mass_llt_->matrixL().solveInPlace(t);
    scaled_ = t.transpose();
  } else {
    scaled_ = jacobian * inverse_sqrt_.head(n).asDiagonal();
  }
  // SVD of A^T (n x m, thin): A^T = V S U^T, so A = U S V^T.
  Eigen::JacobiSVD<InverseJacobian> svd(scaled_.transpose(), Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto& s = svd.singularValues();
  singular_values_ = s;
  const double largest = s.size() > 0 ? s[0] : 0.0;
  rank_ = 0;
  TaskVector f = TaskVector::Zero(m);
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (kind_ == InverseKind::damped) {
      f[i] = s[i] / (s[i] * s[i] + damping_ * damping_);
      if (s[i] > tolerance_ * largest) ++rank_;
    } else if (s[i] > tolerance_ * largest && s[i] > 0.0) {
      f[i] = 1.0 / s[i];
      ++rank_;
    }
  }
  // A# = V_A diag(f) U_A^T; with A^T = U_svd S V_svd^T: V_A = U_svd (n x m), U_A = V_svd (m x m).
  inverse_.noalias() = svd.matrixU() * f.asDiagonal() * svd.matrixV().transpose();
  // J^W# = L^-T A#.
  if (mass_llt_ != nullptr) {
    mass_llt_->matrixU().solveInPlace(inverse_);
  } else {
    inverse_ = inverse_sqrt_.head(n).asDiagonal() * inverse_;
  }
  projector_.setIdentity(n, n);
  projector_.noalias() -= inverse_ * jacobian;
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
  qd.noalias() += inverse.null_space_projector() * qd0;
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
