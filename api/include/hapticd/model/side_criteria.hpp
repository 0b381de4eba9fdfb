#pragma once
// Side criteria for the null space of a redundant chain ([U06] methods 3), written as costs H(q)
// to minimise, and their weighted sum with its gradient. The null-space term descends along it:
// qd0 = -k W^-1 grad H. Criteria (each with its own weight; 0 leaves it out):
//   manipulability            H = -sqrt(det(J J^T))
//   condition_number          H = sigma_max / sigma_min of J (angular rows scaled by a characteristic length)
//   smallest_singular_value   H = -sigma_min
//   wrist                     H = (q_k - target)^2 / (pi/2)^2   (ViSHaRD10: joint 9, target pi/2)
//   joint_limits              H = sum over limited joints of ((q - mid) / range)^2
//   keep_out                  H = (max(0, margin - d) / margin)^2, d: distance from a frame's origin to the
//                             surface of a keep-out sphere (a second device, the operator's body)
// Every gradient is analytic: the singular values' through the Jacobian's derivative, which for a serial chain
// follows from the Jacobian itself (side_criteria.cpp: O(n) per criterion), the keep-out distance's through the
// frame's Jacobian. One evaluation of the kinematics and one 6 x 6 eigen-decomposition per call (manipulability
// alone: a Cholesky factorisation). Real-time safe after configure (its own model workspace).
#include <Eigen/Eigenvalues>
#include <memory>

#include "hapticd/export.hpp"
#include "hapticd/model/model_data.hpp"

namespace hapticd::model {

struct SideCriteriaSettings {
  int frame = -1;                        // the handle frame (Jacobian criteria)
  int task_rows = 6;                     // 3: translation rows only
  double characteristic_length_m = 0.3;  // scales angular rows against linear ones (condition number)
  double manipulability = 0.0;
  double condition_number = 0.0;
  double smallest_singular_value = 0.0;
  double wrist = 0.0;
  int wrist_joint = 8;  // 0-based (ViSHaRD10's joint 9)
  double wrist_target_rad = 1.5707963267948966;
  double joint_limits = 0.0;
  double keep_out = 0.0;
  int keep_out_frame = -1;  // default: the handle frame
  Eigen::Vector3d keep_out_center = Eigen::Vector3d::Zero();
  double keep_out_radius_m = 0.1;
  double keep_out_margin_m = 0.1;
};

class HAPTICD_API SideCriteria {
 public:
  SideCriteria();
  ~SideCriteria();
  SideCriteria(SideCriteria&&) noexcept;
  SideCriteria& operator=(SideCriteria&&) noexcept;

  // Not real-time safe. Throws std::invalid_argument for an out-of-range joint or frame.
  void configure(const RobotModel& model, const SideCriteriaSettings& settings);
  [[nodiscard]] bool empty() const noexcept;
  [[nodiscard]] const SideCriteriaSettings& settings() const noexcept { return settings_; }

  // H(q) and its gradient. Real-time safe. kinematics: a workspace of the same model whose forward kinematics
  // are already at q (the server's model terms at the measured joints: ChainState::data), saving their
  // evaluation; used only if its q equals q.
  double evaluate(const JointVector& q, JointVector& gradient, const ModelData* kinematics = nullptr) noexcept;
  // H(q) alone.
  [[nodiscard]] double value(const JointVector& q) noexcept;

 private:
  [[nodiscard]] double joint_terms(const JointVector& q, JointVector* gradient) const noexcept;
  // The Jacobian and distance terms and (gradient not null) their gradients added, with the kinematics at q.
  [[nodiscard]] double kinematic_terms(const ModelData& at_q, JointVector* gradient) noexcept;
  [[nodiscard]] double keep_out_term(const ModelData& at_q, JointVector* gradient) noexcept;
  [[nodiscard]] bool has_kinematic_terms() const noexcept;

  const RobotModel* model_ = nullptr;
  std::unique_ptr<ModelData> data_;
  SideCriteriaSettings settings_;
  TaskJacobian jacobian_, keep_out_jacobian_, scaled_;
  TaskJacobian derivative_by_jacobian_;  // dH/dJ (6 x n) of the Jacobian criteria
  TaskMatrix gram_;
  Eigen::SelfAdjointEigenSolver<TaskMatrix> eigen_;
  Eigen::LLT<TaskMatrix> gram_llt_;         // manipulability alone
  TaskVector sigma_ = TaskVector::Zero(6);  // singular values, largest first
};

}  // namespace hapticd::model
