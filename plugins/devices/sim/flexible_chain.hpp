#pragma once
// The physics of a simulated device: rigid links (the robot model without drive inertia) coupled through
// each joint's harmonic-drive spring (GearSpring, light structural damping) to the motor and wave-generator
// inertia (reflected to the joint output). Motor side: drive torque, gear friction (JointFriction) and the
// position-dependent torque ripple at 2 cycles per motor revolution. Semi-implicit Euler in substeps.
// Real-time safe after construction.
#include <array>
#include <vector>

#include "gear_spring.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/robot_model.hpp"
#include "joint_friction.hpp"

namespace hapticd::sim {

struct JointPhysics {
  GearSpring spring;
  double motor_inertia = 0.2;     // reflected rotor + wave generator [kg m^2]
  double damping = 0.0;           // structural damping across the spring [N m s/rad]
  double ripple_amplitude = 0.0;  // [N m]
  double ripple_phase = 0.0;      // [rad]
  double gear_ratio = 100.0;
  FrictionParameters friction;
};

class FlexibleChain {
 public:
  // link_model: the rigid-link model (reflected inertia removed); joints: one entry per joint.
  FlexibleChain(model::RobotModel link_model, std::vector<JointPhysics> joints, int handle_frame, std::uint64_t seed);

  // Everything at rest at q0 (springs relaxed under gravity: the motors are placed at q0 + g/k).
  void reset(const JointVector& q0) noexcept;
  // Kinematics of the current state (body poses and velocities, the handle's Jacobian). step() runs it
  // itself unless it ran since the last step, so callers that need the handle's pose first pay nothing.
  void prepare() noexcept;
  [[nodiscard]] Eigen::Isometry3d handle_pose() const noexcept;
  [[nodiscard]] model::Vector6d handle_twist() const noexcept;  // [linear; angular], world
  // Advances by dt under the motor torques and an external wrench on the handle ([force; torque], world).
  void step(double dt, const JointVector& motor_torque, const model::Vector6d& handle_wrench) noexcept;
  // Holds the links still (isometric tests): only the motors move.
  void set_links_locked(bool locked) noexcept { links_locked_ = locked; }

  [[nodiscard]] int dof() const noexcept { return n_; }
  [[nodiscard]] const JointVector& link_position() const noexcept { return q_; }
  [[nodiscard]] const JointVector& link_velocity() const noexcept { return qd_; }
  [[nodiscard]] const JointVector& motor_position() const noexcept { return theta_; }
  [[nodiscard]] const JointVector& motor_velocity() const noexcept { return theta_d_; }
  [[nodiscard]] const JointVector& spring_torque() const noexcept { return spring_torque_; }
  [[nodiscard]] const JointVector& friction_torque() const noexcept { return friction_torque_; }
  [[nodiscard]] const JointVector& link_acceleration() const noexcept { return qdd_; }
  [[nodiscard]] const model::RobotModel& link_model() const noexcept { return model_; }
  [[nodiscard]] model::ModelData& data() noexcept { return data_; }
  [[nodiscard]] const JointPhysics& joint(int i) const { return joints_[static_cast<std::size_t>(i)]; }
  [[nodiscard]] JointFriction& friction(int i) { return friction_[static_cast<std::size_t>(i)]; }
  // Kinetic + gravitational + spring energy (for conservation tests).
  [[nodiscard]] double energy() noexcept;
  // Highest natural frequency estimate of the spring-inertia pairs at the current pose [rad/s].
  [[nodiscard]] double highest_frequency() noexcept;

 private:
  model::RobotModel model_;
  model::ModelData data_;
  std::vector<JointPhysics> joints_;
  std::vector<JointFriction> friction_;
  int n_;
  int handle_;
  bool links_locked_ = false;
  bool prepared_ = false;
  JointVector q_, qd_, qdd_, theta_, theta_d_, spring_torque_, friction_torque_, tau_;
  model::TaskJacobian jacobian_;
};

}  // namespace hapticd::sim
