#include "handle_attachment.hpp"

namespace hapticd::sim {

Vector6d HandleAttachment::step(double t, double dt, const Eigen::Isometry3d& handle, const Vector6d& twist) noexcept {
  const Eigen::Vector3d p = handle.translation();
  const Eigen::Vector3d v = twist.head<3>();
  const Eigen::Vector3d w = twist.tail<3>();
  if (!anchored_) {
    anchored_ = true;
    anchor_time_ = t;
    anchor_position_ = p;
    anchor_rotation_ = handle.linear();
    hand_position_ = p;
    hand_velocity_ = v;
    hand_rotation_.setZero();
    hand_angular_velocity_ = w;
  }
  const double local_t = t - anchor_time_;
  Vector6d wrench = Vector6d::Zero();
  // Rotation of the handle away from its orientation at the anchor, as a rotation vector (world).
  const Eigen::AngleAxisd rotation(handle.linear() * anchor_rotation_.transpose());
  const Eigen::Vector3d rotation_error = rotation.axis() * rotation.angle();
  switch (settings_.kind) {
    case AttachmentKind::none:
      break;
    case AttachmentKind::operator_hand: {
      const AttachmentSettings& s = settings_;
      const Eigen::Vector3d grasp_force =
          s.grasp_stiffness.at(s.grasp) * (hand_position_ - p) + s.grasp_damping.at(s.grasp) * (hand_velocity_ - v);
      const Eigen::Vector3d target = anchor_position_ + s.motion.at(local_t);
      const Eigen::Vector3d target_velocity = s.motion.rate_at(local_t);
      const Eigen::Vector3d arm_force =
          s.arm_stiffness * (target - hand_position_) + s.arm_damping * (target_velocity - hand_velocity_);
      hand_velocity_ += dt * (arm_force + s.force.at(local_t) - grasp_force) / s.hand_mass_kg;
      hand_position_ += dt * hand_velocity_;
      wrench.head<3>() = grasp_force;
      // Rotation: the hand's rotation vector and the handle's, both from the anchor orientation (their
      // difference is the grasp's twist for the moderate angles a hand holds a handle through).
      const Eigen::Vector3d grasp_torque =
          s.grasp_rotational_stiffness.at(s.grasp) * (hand_rotation_ - rotation_error) +
          s.grasp_rotational_damping.at(s.grasp) * (hand_angular_velocity_ - w);
      const Eigen::Vector3d arm_torque =
          s.arm_rotational_stiffness * (s.rotation.at(local_t) - hand_rotation_) +
          s.arm_rotational_damping * (s.rotation.rate_at(local_t) - hand_angular_velocity_);
      hand_angular_velocity_ += dt * (arm_torque + s.torque.at(local_t) - grasp_torque) / s.hand_inertia_kg_m2;
      hand_rotation_ += dt * hand_angular_velocity_;
      wrench.tail<3>() = grasp_torque;
      break;
    }
    case AttachmentKind::position_source: {
      const AttachmentSettings& s = settings_;
      const Eigen::Vector3d target = anchor_position_ + s.path.at(local_t);
      wrench.head<3>() = s.source_stiffness * (target - p) + s.source_damping * (s.path.rate_at(local_t) - v);
      wrench.tail<3>() = -s.source_rotational_stiffness * rotation_error - s.source_rotational_damping * w;
      break;
    }
    case AttachmentKind::wrench:
      wrench.head<3>() = settings_.wrench_force.at(local_t);
      wrench.tail<3>() = settings_.wrench_torque.at(local_t);
      break;
  }
  return wrench;
}

}  // namespace hapticd::sim
