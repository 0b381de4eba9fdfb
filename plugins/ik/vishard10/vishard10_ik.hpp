#pragma once
// Inverse kinematics `vishard10_ik`: the ViSHaRD10 partitioned solution (partitioned_solution.hpp,
// docs/redundancy.md). Joints 6 and 7 always mimic a prismatic joint (the height). The x-y position by the
// SCARA inverse function (two prismatic pairs), the optimised look-up table of plugins/ik/vishard10/scara_lut, or a
// pseudoinverse of joints 1-4 with a manipulability criterion; the orientation by the wrist inverse function (link 5
// keeps the world yaw q5_0) or the weighted wrist pseudoinverse (weights on q5', q8', q9, q10; the criterion (q9 -
// pi/2)^2 and a virtual wall keeping q9 in [zeta, pi - zeta]). With both inverse functions the whole map from handle
// pose to joints is a function: closed handle paths give closed joint paths. The joint target's rates are
// differentiated from its positions (for joint-space controllers: computed torque).
#include <memory>

#include "hapticd/inverse_kinematics.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/redundancy.hpp"
#include "hapticd/signal/differentiator.hpp"
#include "partitioned_solution.hpp"
#include "scara_table.hpp"

namespace hapticd::ik {

class Vishard10Ik final : public InverseKinematics {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const InverseKinematicsInput& current) override;
  Outcome update(const CycleTime& cycle, const InverseKinematicsInput& input, JointTarget& target) override;
  void deactivate() override {}

  // For tests: the joint vector of a handle pose in the device's base frame (inverse functions only; pseudoinverse
  // parts integrate). dt: the step the integrated parts take.
  const JointVector& solve(const Pose& pose, const Twist& twist, double dt) noexcept;
  // Starts the integrated parts (pseudoinverses) and the unwrapping from a posture (activate() does this with
  // the measured one).
  void reset(const JointVector& q) noexcept;
  [[nodiscard]] std::uint64_t clamped_cycles() const noexcept { return clamped_; }

 private:
  void solve_scara(const Eigen::Vector2d& target, const Eigen::Vector2d& velocity, double dt) noexcept;
  void solve_wrist(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& angular_velocity, double dt) noexcept;

  // The partitioned solution works in the device's base frame: the server's model (world frame, PluginContext)
  // taken back to the base, and the base pose that maps the world-frame targets there.
  std::unique_ptr<const model::RobotModel> model_;
  std::unique_ptr<model::ModelData> data_;
  Eigen::Isometry3d world_to_base_ = Eigen::Isometry3d::Identity();
  int handle_ = -1;
  vishard10::Geometry geometry_;
  enum class Scara { inverse_function, lookup_table, pseudoinverse };
  Scara scara_ = Scara::inverse_function;
  bool wrist_function_ = true;
  vishard10::ScaraTable table_;
  double scara_yaw_ = 0.0, scara_limit_ = 0.999;
  int branch12_ = 1, branch34_ = 1;
  double scara_manipulability_ = 1.0;
  double q5_0_ = 0.0;
  double wrist_criterion_ = 1.0, wall_zeta_ = 0.35, wall_gain_ = 50.0;
  double kp_ = 100.0;
  double activation_tolerance_ = 0.05;
  JointVector wrist_weights_;
  model::GeneralizedInverse wrist_inverse_;
  double scara_q_[4] = {0, 0, 0, 0};  // joints 1-4 (pseudoinverse: integrated)
  double rot_q_[4] = {0, 0, 0, 0};    // q5', q8', q9, q10 (pseudoinverse: integrated)
  JointVector q_, previous_, qd_;
  bool first_ = true;
  std::uint64_t clamped_ = 0;
  signal::Differentiator<JointVector> acceleration_;
  model::TaskJacobian jacobian_;
};

}  // namespace hapticd::ik
