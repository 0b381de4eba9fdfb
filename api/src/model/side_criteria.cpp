#include "hapticd/model/side_criteria.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/robot_model.hpp"

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
  probe_.setZero(n);
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

double SideCriteria::kinematic_terms(const JointVector& q) noexcept {
  const SideCriteriaSettings& s = settings_;
  forward_kinematics(*model_, *data_, q);
  double h = 0.0;
  if (s.manipulability != 0.0 || s.condition_number != 0.0 || s.smallest_singular_value != 0.0) {
    frame_jacobian(*model_, *data_, s.frame, jacobian_);
    TaskJacobian j = jacobian_.topRows(s.task_rows);
    if (s.task_rows > 3) j.bottomRows(s.task_rows - 3) *= s.characteristic_length_m;
    const Eigen::JacobiSVD<TaskJacobian> svd(j);
    const auto& sigma = svd.singularValues();
    const double smallest = sigma[sigma.size() - 1];
    if (s.manipulability != 0.0) h -= s.manipulability * sigma.prod();  // sqrt(det(J J^T)) = prod(sigma)
    if (s.condition_number != 0.0) h += s.condition_number * (smallest > 1e-12 ? sigma[0] / smallest : 1e12);
    if (s.smallest_singular_value != 0.0) h -= s.smallest_singular_value * smallest;
  }
  if (s.keep_out != 0.0) {
    const Eigen::Vector3d p = frame_pose(*model_, *data_, s.keep_out_frame).translation();
    const double d = (p - s.keep_out_center).norm() - s.keep_out_radius_m;
    const double intrusion = std::max(0.0, s.keep_out_margin_m - d) / s.keep_out_margin_m;
    h += s.keep_out * intrusion * intrusion;
  }
  return h;
}

double SideCriteria::value(const JointVector& q) noexcept {
  return joint_terms(q, nullptr) + (has_kinematic_terms() ? kinematic_terms(q) : 0.0);
}

double SideCriteria::evaluate(const JointVector& q, JointVector& gradient) noexcept {
  gradient.setZero(q.size());
  double h = joint_terms(q, &gradient);
  if (!has_kinematic_terms()) return h;
  const double base = kinematic_terms(q);
  probe_ = q;
  for (int i = 0; i < q.size(); ++i) {
    probe_[i] = q[i] + settings_.gradient_step;
    gradient[i] += (kinematic_terms(probe_) - base) / settings_.gradient_step;
    probe_[i] = q[i];
  }
  return h + base;
}

}  // namespace hapticd::model
