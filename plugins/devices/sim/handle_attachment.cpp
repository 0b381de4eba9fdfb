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
          grasp_stiffness() * (hand_position_ - p) + grasp_damping() * (hand_velocity_ - v);
      const Eigen::Vector3d target = anchor_position_ + s.motion.at(local_t);
      const Eigen::Vector3d target_velocity = s.motion.rate_at(local_t);
      const Eigen::Vector3d arm_force =
          s.arm_stiffness * (target - hand_position_) + s.arm_damping * (target_velocity - hand_velocity_);
      hand_velocity_ += dt * (arm_force + s.force.at(local_t) - grasp_force) / s.hand_mass_kg;
      hand_position_ += dt * hand_velocity_;
      wrench.head<3>() = grasp_force;
      // The wrist holds the handle's orientation softly.
      wrench.tail<3>() = -(0.5 + 5.0 * s.grasp) * rotation_error - (0.02 + 0.2 * s.grasp) * w;
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
