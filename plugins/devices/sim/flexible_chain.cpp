#include "flexible_chain.hpp"

#include <algorithm>
#include <cmath>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"

namespace hapticd::sim {

FlexibleChain::FlexibleChain(model::RobotModel link_model, std::vector<JointPhysics> joints, int handle_frame,
                             std::uint64_t seed)
    : model_(std::move(link_model)),
      data_(model_),
      probe_(model_),
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
  bias_.setZero(n_);
  q_held_ = q_;
  zero_.setZero(n_);
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
  since_rigid_body_ = 0;
}

void FlexibleChain::set_rigid_body_every(int substeps) noexcept {
  rigid_body_every_ = std::max(1, substeps);
  since_rigid_body_ = 0;
}

void FlexibleChain::evaluate_rigid_body_terms() noexcept {
  // At the middle of the interval they are held for (the configuration extrapolated with the current velocity):
  // a centred hold, second order in the interval where holding them from its start is first order.
  q_held_ = q_;
  if (rigid_body_every_ > 1) q_held_ += qd_ * (0.5 * (rigid_body_every_ - 1) * last_dt_);
  model::forward_velocity(model_, data_, q_held_, qd_);
  model::frame_jacobian(model_, data_, handle_, jacobian_);
  held_pose_ = model::frame_pose(model_, data_, handle_);
  held_jacobian_rate_ = model::frame_jacobian_dot_times_qd(model_, data_, handle_);
  if (!links_locked_) {
    model::joint_space_inertia(model_, data_);
    model::inverse_dynamics(model_, data_, zero_, bias_);  // C qd + g
    // Held over several substeps, M^-1 explicitly: a matrix-vector product per substep costs less than two
    // triangular solves.
    if (rigid_body_every_ > 1) {
      inverse_mass_.setIdentity(n_, n_);
      data_.mass_llt.solveInPlace(inverse_mass_);
    }
  }
}

void FlexibleChain::prepare() noexcept {
  if (since_rigid_body_ == 0) evaluate_rigid_body_terms();
  // The handle at q, to first order in dq = q - q_held: the linear rows move the point, the angular ones turn
  // the frame.
  const JointVector dq = q_ - q_held_;
  const model::Vector6d moved = jacobian_ * dq;
  handle_pose_.translation() = held_pose_.translation() + moved.head<3>();
  const double angle = moved.tail<3>().norm();
  handle_pose_.linear() = angle > 0.0
                              ? Eigen::Matrix3d(Eigen::AngleAxisd(angle, moved.tail<3>() / angle) * held_pose_.linear())
                              : held_pose_.linear();
  prepared_ = true;
}

FlexibleChain::FrameAcceleration FlexibleChain::frame_acceleration(int frame_id) noexcept {
  model::forward_velocity(model_, probe_, q_, qd_, model::BodyInertias::skip);
  model::frame_jacobian(model_, probe_, frame_id, probe_jacobian_);
  FrameAcceleration out{model::frame_pose(model_, probe_, frame_id), model::Vector6d::Zero()};
  out.acceleration.noalias() = probe_jacobian_ * qdd_;
  out.acceleration += model::frame_jacobian_dot_times_qd(model_, probe_, frame_id);
  return out;
}

model::Vector6d FlexibleChain::handle_twist() const noexcept {
  // J(q) qd with J to first order in time about the held point: J qd + (t - t_held) dJ/dt qd. Without the
  // second term the twist would jump whenever the terms are evaluated again (a spike in its differences: the
  // sensor's inertial force).
  model::Vector6d twist = jacobian_ * qd_;
  if (rigid_body_every_ > 1)
    twist += held_jacobian_rate_ * ((since_rigid_body_ - 0.5 * (rigid_body_every_ - 1)) * last_dt_);
  return twist;
}

Eigen::Isometry3d FlexibleChain::carried_frame_pose(int frame_id) const noexcept {
  // On the handle's link: its pose at q_held_ moved as the handle moved since. Elsewhere: as at q_held_.
  const Eigen::Isometry3d held = model::frame_pose(model_, data_, frame_id);
  if (model_.frame(frame_id).body != model_.frame(handle_).body) return held;
  return handle_pose_ * held_pose_.inverse() * held;
}

void FlexibleChain::step(double dt, const JointVector& motor_torque, const model::Vector6d& handle_wrench) noexcept {
  last_dt_ = dt;
  if (!prepared_) prepare();
  prepared_ = false;
  for (int i = 0; i < n_; ++i) {
    const JointPhysics& j = joints_[static_cast<std::size_t>(i)];
    spring_torque_[i] = j.spring.torque(theta_[i] - q_[i]) + j.damping * (theta_d_[i] - qd_[i]);
  }
  // Links: qdd = M^-1 (tau_spring + J^T F - C qd - g) with the held rigid-body terms.
  if (!links_locked_) {
    tau_ = spring_torque_ - bias_;
    tau_.noalias() += jacobian_.transpose() * handle_wrench;
    if (rigid_body_every_ > 1) {
      qdd_.noalias() = inverse_mass_ * tau_;
    } else {
      qdd_ = tau_;
      data_.mass_llt.solveInPlace(qdd_);
    }
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
  if (++since_rigid_body_ >= rigid_body_every_) since_rigid_body_ = 0;
}

double FlexibleChain::energy() noexcept {
  prepared_ = false;
  since_rigid_body_ = 0;
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
  since_rigid_body_ = 0;
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
