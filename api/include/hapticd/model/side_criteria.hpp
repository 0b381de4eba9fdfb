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
// The joint criteria have analytic gradients; the Jacobian and distance ones forward differences (n + 1
// evaluations of the kinematics). Real-time safe after configure (its own model workspace).
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
  double gradient_step = 1e-6;  // forward-difference step [rad]
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

  // H(q) and its gradient. Real-time safe.
  double evaluate(const JointVector& q, JointVector& gradient) noexcept;
  // H(q) alone.
  [[nodiscard]] double value(const JointVector& q) noexcept;

 private:
  [[nodiscard]] double joint_terms(const JointVector& q, JointVector* gradient) const noexcept;
  [[nodiscard]] double kinematic_terms(const JointVector& q) noexcept;  // needs the kinematics at q
  [[nodiscard]] bool has_kinematic_terms() const noexcept;

  const RobotModel* model_ = nullptr;
  std::unique_ptr<ModelData> data_;
  SideCriteriaSettings settings_;
  TaskJacobian jacobian_;
  JointVector probe_;
};

}  // namespace hapticd::model
