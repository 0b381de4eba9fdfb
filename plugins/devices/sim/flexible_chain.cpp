#include "flexible_chain.hpp"

#include <cmath>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"

namespace hapticd::sim {

FlexibleChain::FlexibleChain(model::RobotModel link_model, std::vector<JointPhysics> joints, int handle_frame,
                             std::uint64_t seed)
    : model_(std::move(link_model)),
      data_(model_),
      joints_(std::move(joints)),
      friction_(joints_.size()),
      n_(model_.dof()),
      handle_(handle_frame) {
  for (int i = 0; i < n_; ++i) {
    friction_[static_cast<std::size_t>(i)].configure(joints_[static_cast<std::size_t>(i)].friction,
                                                     seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(i) + 1);
  }
  reset(JointVector::Zero(n_));
}

void FlexibleChain::reset(const JointVector& q0) noexcept {
  q_ = q0;
  qd_.setZero(n_);
  qdd_.setZero(n_);
  theta_d_.setZero(n_);
  friction_torque_.setZero(n_);
  tau_.setZero(n_);
  model::forward_kinematics(model_, data_, q_);
  model::gravity_torques(model_, data_);
  theta_.resize(n_);
  spring_torque_.resize(n_);
  for (int i = 0; i < n_; ++i) {
    // Spring pre-loaded to carry gravity: find d with spring(d) = g_i (Newton on the monotone spring).
    const GearSpring& s = joints_[static_cast<std::size_t>(i)].spring;
    double d = data_.gravity_torque[i] / s.k_min;
    for (int it = 0; it < 30; ++it) d -= (s.torque(d) - data_.gravity_torque[i]) / s.stiffness(d);
    theta_[i] = q_[i] + d;
    spring_torque_[i] = s.torque(d);
  }
  for (auto& f : friction_) f.reset();
  prepared_ = false;
}

void FlexibleChain::prepare() noexcept {
  model::forward_velocity(model_, data_, q_, qd_);
  model::frame_jacobian(model_, data_, handle_, jacobian_);
  prepared_ = true;
}

Eigen::Isometry3d FlexibleChain::handle_pose() const noexcept { return model::frame_pose(model_, data_, handle_); }

model::Vector6d FlexibleChain::handle_twist() const noexcept { return jacobian_ * qd_; }

void FlexibleChain::step(double dt, const JointVector& motor_torque, const model::Vector6d& handle_wrench) noexcept {
  if (!prepared_) prepare();
  prepared_ = false;
  for (int i = 0; i < n_; ++i) {
    const JointPhysics& j = joints_[static_cast<std::size_t>(i)];
    spring_torque_[i] = j.spring.torque(theta_[i] - q_[i]) + j.damping * (theta_d_[i] - qd_[i]);
  }
  // Links.
  if (!links_locked_) {
    tau_ = spring_torque_;
    tau_.noalias() += jacobian_.transpose() * handle_wrench;
    model::forward_dynamics(model_, data_, tau_, qdd_);
  } else {
    qdd_.setZero(n_);
    qd_.setZero(n_);
  }
  // Motors.
  for (int i = 0; i < n_; ++i) {
    const JointPhysics& j = joints_[static_cast<std::size_t>(i)];
    JointFriction& f = friction_[static_cast<std::size_t>(i)];
    f.advance_temperature(dt);
    const double ripple = j.ripple_amplitude * std::sin(2.0 * j.gear_ratio * theta_[i] + j.ripple_phase);
    const double drive = motor_torque[i] - spring_torque_[i] + ripple;
    double friction = 0.0;
    theta_d_[i] = f.step_velocity(theta_d_[i], drive, spring_torque_[i], j.motor_inertia, dt, friction);
    friction_torque_[i] = friction;
    theta_[i] += theta_d_[i] * dt;
  }
  qd_ += qdd_ * dt;
  q_ += qd_ * dt;
}

double FlexibleChain::energy() noexcept {
  prepared_ = false;
  model::forward_kinematics(model_, data_, q_);
  model::joint_space_inertia(model_, data_);
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  for (int i = 0; i < n_; ++i) first_moment += data_.inertia[static_cast<std::size_t>(i)].first_moment;
  double e = 0.5 * qd_.dot(data_.mass_matrix * qd_) - model_.gravity().dot(first_moment);
  for (int i = 0; i < n_; ++i) {
    const JointPhysics& j = joints_[static_cast<std::size_t>(i)];
    e += 0.5 * j.motor_inertia * theta_d_[i] * theta_d_[i] + j.spring.potential(theta_[i] - q_[i]);
  }
  return e;
}

double FlexibleChain::highest_frequency() noexcept {
  prepared_ = false;
  model::forward_kinematics(model_, data_, q_);
  model::joint_space_inertia(model_, data_);
  // Per joint: spring k_max between the motor inertia and the link's apparent inertia 1 / (M^-1)_ii.
  JointMatrix inverse = JointMatrix::Identity(n_, n_);
  data_.mass_llt.solveInPlace(inverse);
  double highest = 0.0;
  for (int i = 0; i < n_; ++i) {
    const JointPhysics& j = joints_[static_cast<std::size_t>(i)];
    highest = std::max(highest, std::sqrt(j.spring.k_max * (1.0 / j.motor_inertia + inverse(i, i))));
  }
  return highest;
}

}  // namespace hapticd::sim
