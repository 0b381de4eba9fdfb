#pragma once
// What is attached to the simulated handle: nothing; a simulated operator (a hand-arm mass and rotational
// inertia pulled by the arm towards a target motion and rotation, plus a voluntary force and torque, holding the
// handle through a grasp spring-damper, translational and rotational, from loose to firm); a stiff position source (a
// linear guide with coupling stiffness and damping following a path); or a scripted wrench. Settings can be replaced at
// any time; the new attachment starts from the handle's current pose (no jump). Real-time safe.
#include <Eigen/Geometry>
#include <cmath>

#include "profile.hpp"

namespace hapticd::sim {

using Vector6d = Eigen::Matrix<double, 6, 1>;

enum class AttachmentKind { none, operator_hand, position_source, wrench };

struct AttachmentSettings {
  AttachmentKind kind = AttachmentKind::none;
  // Operator.
  double grasp = 0.5;  // 0 loose .. 1 firm
  double hand_mass_kg = 1.5;
  // The grasp's stiffness and damping at a loose (grasp 0) and a firm (grasp 1) grasp, geometric between.
  double loose_grasp_stiffness = 100.0;   // [N/m]
  double firm_grasp_stiffness = 30000.0;  // [N/m]
  double loose_grasp_damping = 2.0;       // [N s/m]
  double firm_grasp_damping = 30.0;       // [N s/m]
  // Selected again with the same kind: keep the anchor, the hand's state and the profiles' clock (a move).
  bool keep_anchor = false;
  double arm_stiffness = 300.0;  // [N/m] towards the target motion
  double arm_damping = 25.0;     // [N s/m]
  Profile motion;                // target offset from the grasp position [m]
  Profile force;                 // voluntary force [N]
  // The same in rotation: the hand's rotational inertia held by the grasp's rotational spring-damper [loose,
  // firm] (geometric between, as the translational one) and pulled by the arm towards a target rotation.
  double hand_inertia_kg_m2 = 0.005;
  double loose_grasp_rotational_stiffness = 0.5;  // [N m/rad]
  double firm_grasp_rotational_stiffness = 50.0;  // [N m/rad]
  double loose_grasp_rotational_damping = 0.02;   // [N m s/rad]
  double firm_grasp_rotational_damping = 0.5;     // [N m s/rad]
  double arm_rotational_stiffness = 5.0;          // [N m/rad] towards the target rotation
  double arm_rotational_damping = 0.2;            // [N m s/rad]
  Profile rotation;                               // target rotation from the grasp orientation (rotation vector) [rad]
  Profile torque;                                 // voluntary torque [N m]
  // Position source.
  double source_stiffness = 1e5;               // [N/m]
  double source_damping = 500.0;               // [N s/m]
  double source_rotational_stiffness = 500.0;  // [N m/rad]
  double source_rotational_damping = 5.0;      // [N m s/rad]
  Profile path;                                // offset from the attach position [m]
  // Scripted wrench.
  Profile wrench_force;   // [N]
  Profile wrench_torque;  // [N m]
};

class HandleAttachment {
 public:
  // Replaces the settings; the attachment re-anchors at the next step at the handle's pose then, unless the
  // settings keep the anchor (the same operator's hand, a new motion on the same clock).
  void select(const AttachmentSettings& settings) noexcept {
    const bool keep = settings.keep_anchor && settings.kind == settings_.kind;
    settings_ = settings;
    if (!keep) anchored_ = false;
  }
  [[nodiscard]] const AttachmentSettings& settings() const noexcept { return settings_; }

  // The wrench ([force; torque], world, at the handle point) the attachment applies to the handle over the
  // next dt, given the handle's pose and twist ([linear; angular]); t is the simulated time.
  Vector6d step(double t, double dt, const Eigen::Isometry3d& handle, const Vector6d& twist) noexcept;

  // Grasp stiffness and damping of the operator at the current grasp setting: geometric between loose and firm
  // (the values span two orders of magnitude; co-contraction raises them multiplicatively).
  [[nodiscard]] double grasp_stiffness() const noexcept {
    return between(settings_.loose_grasp_stiffness, settings_.firm_grasp_stiffness);
  }
  [[nodiscard]] double grasp_damping() const noexcept {
    return between(settings_.loose_grasp_damping, settings_.firm_grasp_damping);
  }
  [[nodiscard]] double grasp_rotational_stiffness() const noexcept {
    return between(settings_.loose_grasp_rotational_stiffness, settings_.firm_grasp_rotational_stiffness);
  }
  [[nodiscard]] double grasp_rotational_damping() const noexcept {
    return between(settings_.loose_grasp_rotational_damping, settings_.firm_grasp_rotational_damping);
  }

 private:
  // Both ends above zero (the parameters' bounds).
  [[nodiscard]] double between(double loose, double firm) const noexcept {
    return loose * std::pow(firm / loose, settings_.grasp);
  }
  AttachmentSettings settings_;
  bool anchored_ = false;
  double anchor_time_ = 0.0;
  Eigen::Vector3d anchor_position_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d anchor_rotation_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d hand_position_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d hand_velocity_ = Eigen::Vector3d::Zero();
  // The hand's rotation from the anchor orientation (a rotation vector, world) and its angular velocity.
  Eigen::Vector3d hand_rotation_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d hand_angular_velocity_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::sim
