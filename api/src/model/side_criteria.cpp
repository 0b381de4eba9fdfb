#include "hapticd/model/side_criteria.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/robot_model.hpp"
#include "triangular_solve.hpp"

namespace hapticd::model {

SideCriteria::SideCriteria() = default;
SideCriteria::~SideCriteria() = default;
SideCriteria::SideCriteria(SideCriteria&&) noexcept = default;
SideCriteria& SideCriteria::operator=(SideCriteria&&) noexcept = default;

void SideCriteria::configure(const RobotModel& model, const SideCriteriaSettings& settings) {
  const int n = model.dof();
  const auto frames = static_cast<int>(model.frames().size());
  if (settings.wrist != 0.0 && (settings.wrist_joint < 0 || settings.wrist_joint >= n))
    throw std::invalid_argument("wrist joint " + std::to_string(settings.wrist_joint + 1) + " outside 1.." +
                                std::to_string(n));
  if (settings.frame < 0 || settings.frame >= frames) throw std::invalid_argument("no frame for the side criteria");
  model_ = &model;
  settings_ = settings;
  if (settings_.keep_out_frame < 0) settings_.keep_out_frame = settings.frame;
  if (settings_.keep_out_frame >= frames) throw std::invalid_argument("keep-out frame out of range");
  data_ = std::make_unique<ModelData>(model);
  jacobian_.setZero(6, n);
  keep_out_jacobian_.setZero(6, n);
  scaled_.setZero(6, n);
  gram_.setZero(6, 6);
  derivative_by_jacobian_.setZero(6, n);
}

bool SideCriteria::empty() const noexcept {
  const SideCriteriaSettings& s = settings_;
  return s.manipulability == 0.0 && s.condition_number == 0.0 && s.smallest_singular_value == 0.0 && s.wrist == 0.0 &&
         s.joint_limits == 0.0 && s.keep_out == 0.0;
}

bool SideCriteria::has_kinematic_terms() const noexcept {
  const SideCriteriaSettings& s = settings_;
  return s.manipulability != 0.0 || s.condition_number != 0.0 || s.smallest_singular_value != 0.0 || s.keep_out != 0.0;
}

double SideCriteria::joint_terms(const JointVector& q, JointVector* gradient) const noexcept {
  const SideCriteriaSettings& s = settings_;
  double h = 0.0;
  if (s.wrist != 0.0) {
    constexpr double kScale = 1.0 / (1.5707963267948966 * 1.5707963267948966);
    const double e = q[s.wrist_joint] - s.wrist_target_rad;
    h += s.wrist * kScale * e * e;
    if (gradient != nullptr) (*gradient)[s.wrist_joint] += 2.0 * s.wrist * kScale * e;
  }
  if (s.joint_limits != 0.0) {
    for (int i = 0; i < q.size(); ++i) {
      const Body& b = model_->body(i);
      if (b.position_min <= -1e8 || b.position_max >= 1e8) continue;  // unlimited
      const double range = b.position_max - b.position_min;
      const double e = (q[i] - 0.5 * (b.position_min + b.position_max)) / range;
      h += s.joint_limits * e * e;
      if (gradient != nullptr) (*gradient)[i] += 2.0 * s.joint_limits * e / range;
    }
  }
  return h;
}

namespace {

// Adds sum over k of <B_k, dJ_k/dq_i> to g_i for every joint i (B: 6 x n, the criterion's derivative by the
// Jacobian's entries), without differentiating numerically. For a serial chain the geometric Jacobian's columns
// J_k = [v_k; w_k] (linear velocity of the frame point, angular velocity) move with q as
//   dJ_k/dq_i = [w_min(i,k) x v_max(i,k); w_i x w_k if i < k, else 0]
// (joint i turns the axes after it and the frame point; the axes before it stay). With the triple product the
// double sum splits into running sums over k:
//   g_i = w_i . (sum_{k >= i} v_k x B_lin,k + sum_{k > i} w_k x B_ang,k) + v_i . sum_{k < i} B_lin,k x w_k,
// O(n) instead of O(n^2).
void add_jacobian_derivative_contraction(const TaskJacobian& j, const TaskJacobian& b, JointVector& g) noexcept {
  const auto n = j.cols();
  Eigen::Vector3d after = Eigen::Vector3d::Zero(), angular_after = Eigen::Vector3d::Zero();
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    after += j.block<3, 1>(0, i).cross(b.block<3, 1>(0, i));
    g[i] += j.block<3, 1>(3, i).dot(after + angular_after);
    angular_after += j.block<3, 1>(3, i).cross(b.block<3, 1>(3, i));
  }
  Eigen::Vector3d before = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    g[i] += j.block<3, 1>(0, i).dot(before);
    before += b.block<3, 1>(0, i).cross(j.block<3, 1>(3, i));
  }
}

}  // namespace

double SideCriteria::kinematic_terms(const ModelData& at_q, JointVector* gradient) noexcept {
  const SideCriteriaSettings& s = settings_;
  double h = 0.0;
  if (s.manipulability != 0.0 || s.condition_number != 0.0 || s.smallest_singular_value != 0.0) {
    frame_jacobian(*model_, at_q, s.frame, jacobian_);
    // J_s = D J (task rows; angular rows scaled by the characteristic length). Its singular values from the
    // eigen-decomposition of G = J_s J_s^T (r x r): sigma_j^2 and u_j. With dsigma_j = u_j^T dJ_s v_j and
    // v_j = J_s^T u_j / sigma_j, a criterion H(sigma) changes by <B, dJ> with
    //   B = D U diag(dH/dsigma_j / sigma_j) U^T J_s.
    const int r = s.task_rows;
    TaskJacobian& js = scaled_;
    js = jacobian_.topRows(r);
    if (r > 3) js.bottomRows(r - 3) *= s.characteristic_length_m;
    gram_.noalias() = js.lazyProduct(js.transpose());  // coefficient-wise: GEMM costs more at 6 x 10
    if (s.condition_number == 0.0 && s.smallest_singular_value == 0.0) {
      // Manipulability alone needs no singular values: sqrt(det G) from G's Cholesky factor, and
      // d sqrt(det G) = sqrt(det G) <G^-1 J_s, dJ_s>.
      gram_llt_.compute(gram_);
      if (gram_llt_.info() == Eigen::Success) {
        const double root_det = gram_llt_.matrixLLT().diagonal().prod();
        h -= s.manipulability * root_det;
        if (gradient != nullptr && root_det > 0.0) {
          derivative_by_jacobian_.setZero(6, jacobian_.cols());
          auto b = derivative_by_jacobian_.topRows(r);
          b = js;
          detail::cholesky_solve_in_place(gram_llt_.matrixLLT(), b);
          b *= -s.manipulability * root_det;
          if (r > 3) b.bottomRows(r - 3) *= s.characteristic_length_m;
          add_jacobian_derivative_contraction(jacobian_, derivative_by_jacobian_, *gradient);
        }
        return h + keep_out_term(at_q, gradient);
      }
    }
    eigen_.compute(gram_);
    const auto& s2 = eigen_.eigenvalues();  // ascending: index e is sigma_[r - 1 - e]
    for (int k = 0; k < r; ++k) sigma_[k] = std::sqrt(std::max(s2[r - 1 - k], 0.0));  // largest first
    const double largest = sigma_[0], smallest = sigma_[r - 1];
    TaskVector dh = TaskVector::Zero(r);  // dH/dsigma_k, largest first
    if (s.manipulability != 0.0) {
      double product = 1.0;
      for (int k = 0; k < r; ++k) product *= sigma_[k];
      h -= s.manipulability * product;  // sqrt(det(J J^T)) = prod(sigma)
      for (int k = 0; k < r; ++k) {
        double others = 1.0;
        for (int l = 0; l < r; ++l)
          if (l != k) others *= sigma_[l];
        dh[k] -= s.manipulability * others;
      }
    }
    if (s.condition_number != 0.0) {
      const bool finite = smallest > 1e-12;
      h += s.condition_number * (finite ? largest / smallest : 1e12);
      if (finite) {
        dh[0] += s.condition_number / smallest;
        dh[r - 1] -= s.condition_number * largest / (smallest * smallest);
      }
    }
    if (s.smallest_singular_value != 0.0) {
      h -= s.smallest_singular_value * smallest;
      dh[r - 1] -= s.smallest_singular_value;
    }
    if (gradient != nullptr) {
      TaskVector c = TaskVector::Zero(r);  // in the eigenvalues' order
      for (int k = 0; k < r; ++k)
        if (sigma_[k] > 1e-12) c[r - 1 - k] = dh[k] / sigma_[k];
      const auto& u = eigen_.eigenvectors();
      gram_.noalias() = u * c.asDiagonal() * u.transpose();
      derivative_by_jacobian_.setZero(6, jacobian_.cols());
      derivative_by_jacobian_.topRows(r).noalias() = gram_.lazyProduct(js);
      if (r > 3) derivative_by_jacobian_.middleRows(3, r - 3) *= s.characteristic_length_m;
      add_jacobian_derivative_contraction(jacobian_, derivative_by_jacobian_, *gradient);
    }
  }
  return h + keep_out_term(at_q, gradient);
}

double SideCriteria::keep_out_term(const ModelData& at_q, JointVector* gradient) noexcept {
  const SideCriteriaSettings& s = settings_;
  if (s.keep_out == 0.0) return 0.0;
  const Eigen::Vector3d p = frame_pose(*model_, at_q, s.keep_out_frame).translation();
  const Eigen::Vector3d offset = p - s.keep_out_center;
  const double distance = offset.norm();
  const double d = distance - s.keep_out_radius_m;
  const double intrusion = std::max(0.0, s.keep_out_margin_m - d) / s.keep_out_margin_m;
  if (gradient != nullptr && intrusion > 0.0 && distance > 0.0) {
    // dH/dq = -2 w intrusion / margin * (p - c)^T / |p - c| * J_p (the frame origin's linear rows).
    frame_jacobian(*model_, at_q, s.keep_out_frame, keep_out_jacobian_);
    gradient->noalias() -= (2.0 * s.keep_out * intrusion / (s.keep_out_margin_m * distance)) *
                           (keep_out_jacobian_.topRows(3).transpose() * offset);
  }
  return s.keep_out * intrusion * intrusion;
}

double SideCriteria::value(const JointVector& q) noexcept {
  double h = joint_terms(q, nullptr);
  if (!has_kinematic_terms()) return h;
  forward_kinematics(*model_, *data_, q, BodyInertias::skip);
  return h + kinematic_terms(*data_, nullptr);
}

double SideCriteria::evaluate(const JointVector& q, JointVector& gradient, const ModelData* kinematics) noexcept {
  gradient.setZero(q.size());
  double h = joint_terms(q, &gradient);
  if (!has_kinematic_terms()) return h;
  // The caller's kinematics where they are at q (the server's model terms at the measured joints), else our own.
  const bool reuse = kinematics != nullptr && kinematics->q.size() == q.size() && kinematics->q == q;
  if (!reuse) forward_kinematics(*model_, *data_, q, BodyInertias::skip);
  return h + kinematic_terms(reuse ? *kinematics : *data_, &gradient);
}

}  // namespace hapticd::model
