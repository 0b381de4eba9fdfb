#pragma once
// The physics of a simulated device: rigid links (the robot model without drive inertia) coupled through
// each joint's harmonic-drive spring (GearSpring, light structural damping) to the motor and wave-generator
// inertia (reflected to the joint output). Motor side: drive torque, gear friction (JointFriction) and the
// position-dependent torque ripple at 2 cycles per motor revolution. Semi-implicit Euler in substeps.
//
// Multirate: the stiff parts - springs, motors, friction, and the links' integration under the spring torques -
// advance every substep; the rigid-body terms - the mass matrix and its factorisation, Coriolis and gravity
// torques, the handle's Jacobian and pose - are evaluated every `rigid_body_every` substeps and held in between
// (the handle's pose then extrapolated to first order: x + J dq). They change with the configuration, slowly
// against the drive springs' oscillation. rigid_body_every 1 is the single-rate integrator
// (docs/simulated-devices.md has the accuracy against it). Real-time safe after construction.
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
  // The rigid-body terms every this many substeps (1: every substep, the single-rate integrator).
  void set_rigid_body_every(int substeps) noexcept;
  [[nodiscard]] int rigid_body_every() const noexcept { return rigid_body_every_; }
  // Kinematics of the current state (body poses and velocities, the handle's Jacobian). step() runs it
  // itself unless it ran since the last step, so callers that need the handle's pose first pay nothing.
  void prepare() noexcept;
  [[nodiscard]] const Eigen::Isometry3d& handle_pose() const noexcept { return handle_pose_; }
  [[nodiscard]] model::Vector6d handle_twist() const noexcept;  // [linear; angular], world
  // A frame carried by the handle's link (the force sensor), at the current substep.
  [[nodiscard]] Eigen::Isometry3d carried_frame_pose(int frame_id) const noexcept;
  // A frame's exact pose and classical acceleration [linear; angular] (world) from the links' last
  // acceleration: its own kinematics, for once-per-cycle readings (accelerometers).
  struct FrameAcceleration {
    Eigen::Isometry3d pose;
    model::Vector6d acceleration;
  };
  [[nodiscard]] FrameAcceleration frame_acceleration(int frame_id) noexcept;
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
  // The held rigid-body terms (after energy() or highest_frequency(): at the current state).
  [[nodiscard]] const model::ModelData& data() const noexcept { return data_; }
  [[nodiscard]] const JointPhysics& joint(int i) const { return joints_[static_cast<std::size_t>(i)]; }
  [[nodiscard]] JointFriction& friction(int i) { return friction_[static_cast<std::size_t>(i)]; }
  // Kinetic + gravitational + spring energy (for conservation tests). Both below evaluate the rigid-body terms
  // at the current state; the next substep evaluates them again.
  [[nodiscard]] double energy() noexcept;
  // Highest natural frequency estimate of the spring-inertia pairs at the current pose [rad/s].
  [[nodiscard]] double highest_frequency() noexcept;

 private:
  model::RobotModel model_;
  model::ModelData data_;
  model::ModelData probe_;  // frame_acceleration's kinematics, apart from the held rigid-body terms
  std::vector<JointPhysics> joints_;
  std::vector<JointFriction> friction_;
  int n_;
  int handle_;
  // The rigid-body terms at q_held_: M^-1 (inverse_mass_), bias_ = C qd + g, jacobian_, held_pose_.
  void evaluate_rigid_body_terms() noexcept;

  bool links_locked_ = false;
  bool prepared_ = false;
  int rigid_body_every_ = 1;
  int since_rigid_body_ = 0;  // substeps since the rigid-body terms (0: due)
  double last_dt_ = 0.0;      // the substep (the centred hold's extrapolation)
  JointVector q_, qd_, qdd_, theta_, theta_d_, spring_torque_, friction_torque_, tau_;
  JointVector bias_, q_held_, zero_;
  JointMatrix inverse_mass_;
  model::TaskJacobian jacobian_, probe_jacobian_;
  Eigen::Isometry3d held_pose_ = Eigen::Isometry3d::Identity();    // the handle at q_held_
  model::Vector6d held_jacobian_rate_ = model::Vector6d::Zero();   // dJ/dt qd there
  Eigen::Isometry3d handle_pose_ = Eigen::Isometry3d::Identity();  // at q_ (extrapolated between evaluations)
};

}  // namespace hapticd::sim
