#pragma once
// The virtual admittance (CONTROL-METHODS.md section 2): the operator's wrench drives a virtual rigid body,
//   translation  M_t xdd + D_t xd = F              (world axes)
//   rotation     M_r wd + w x (M_r w) + D_r w = T  (Euler's equations in the body frame)
// whose pose (a unit quaternion: no representation singularities) is the desired handle pose of the inner
// motion controller. Semi-implicit Euler at the control rate, with integration limits on the velocities.
// Virtual walls (half-spaces: a point and an outward normal of the free side) push the virtual body back with
// a unilateral spring-damper; the wall force is reported as the environment wrench of the target. With
// motion_based the walls act on the measured handle motion instead of the virtual body's (the thesis's
// motion-based impedance control: walls do not drift when the inner loop is not integral).
#include <array>

#include "hapticd/virtual_model.hpp"

namespace hapticd::models {

class VirtualAdmittance final : public VirtualModel {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  ReturnCode activate(const VirtualModelInput& current) noexcept override;
  ReturnCode update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) noexcept override;
  void deactivate() override {}

 private:
  struct Wall {
    Eigen::Vector3d point, normal;
  };
  static constexpr int kMaxWalls = 8;

  Eigen::Vector3d wall_force(const Eigen::Vector3d& position, const Eigen::Vector3d& velocity) const noexcept;

  Eigen::Vector3d mass_, inertia_, damping_, rotational_damping_;
  std::array<Wall, kMaxWalls> walls_{};
  int wall_count_ = 0;
  double wall_stiffness_ = 0.0, wall_damping_ = 0.0;
  bool motion_based_ = false;
  double max_velocity_ = 1.0, max_angular_velocity_ = 5.0;
  bool rotation_ = true;
  double period_s_ = 0.0005;

  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d body_angular_velocity_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::models
