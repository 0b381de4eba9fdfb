#pragma once
// Inverse kinematics `redundancy_ik` for any chain with more joints than task rows ([U06] methods 3;
// docs/redundancy.md): a generalised inverse (pseudoinverse by SVD, weighted, singularity-robust
// damped, or inertia-weighted) with a null-space term descending a weighted sum of side criteria.
//
// Joint target (for joint-space controllers), integrated from the device's state at activation:
//   velocity level      qd_d = J^W# (xd_d + kp e) + N qd0,              qd0 = -k W^-1 grad H
//   acceleration level  qdd_d = J^W# (xdd_d + kd (xd_d - J qd_d) + kp e - Jd qd_d) + N d (qd0 - qd_d)
// with e the pose error between the task target and FK(q_d), q_d integrated each cycle, and grad H taken at the
// measured joints (once per cycle). H includes the clearance to the nearest other device of the group (the group
// stage's distance and its gradient, ChainState::neighbour) when weighted. Task-space controllers get the same
// resolution at the measured state through redundancy() (acceleration and torque level).
#include <memory>

#include "hapticd/inverse_kinematics.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/redundancy.hpp"
#include "hapticd/model/side_criteria.hpp"
#include "hapticd/realtime/latest_value.hpp"
#include "hapticd/signal/differentiator.hpp"

namespace hapticd::ik {

class RedundancyIk final : public InverseKinematics, public RedundancyResolution {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const InverseKinematicsInput& current) override;
  Outcome update(const CycleTime& cycle, const InverseKinematicsInput& input, JointTarget& target) override;
  void deactivate() override {}
  // The tunable null-space gain and damping, taken at the next cycle.
  void tune(const Parameters& parameters) override;
  RedundancyResolution* redundancy() noexcept override { return this; }

  JointVector task_acceleration(const DeviceState& device, const ChainState& chain,
                                const model::TaskVector& xdd_minus_bias) noexcept override;
  JointVector null_space_torque(const DeviceState& device, const ChainState& chain, int rows) noexcept override;

  // For tests and benchmarks.
  [[nodiscard]] const model::GeneralizedInverse& inverse() const noexcept { return inverse_; }
  [[nodiscard]] double criterion() const noexcept { return criterion_; }

 private:
  enum class Level { velocity, acceleration };

  // Adds the clearance criterion's gradient to gradient_; returns its value.
  double add_clearance_term(const NeighbourClearance& neighbour) noexcept;

  const model::RobotModel* model_ = nullptr;  // the server's, shared by the chain (PluginContext)
  std::unique_ptr<model::ModelData> data_;
  int handle_ = -1;
  int rows_ = 3;
  Level level_ = Level::velocity;
  double kp_ = 0.0, kd_ = 0.0;  // pose-error feedback of the integrated target
  double null_gain_ = 0.0;      // k
  double null_damping_ = 0.0;   // d [1/s]
  struct NullSpaceGains {
    double gain = 0.0, damping = 0.0;
  };
  realtime::LatestValue<NullSpaceGains> gains_inbox_;  // tune() -> the loop, at a cycle boundary
  model::GeneralizedInverse inverse_;                  // at the joint target
  model::GeneralizedInverse measured_;                 // at the measured state (task_acceleration)
  model::GeneralizedInverse dynamic_;                  // inertia-weighted at the measured state (null_space_torque)
  model::SideCriteria criteria_;
  JointVector q_, qd_, gradient_;
  double criterion_ = 0.0;
  double clearance_weight_ = 0.0, clearance_margin_ = 0.15;
  signal::Differentiator<JointVector> acceleration_;
  model::TaskJacobian jacobian_;
};

}  // namespace hapticd::ik
