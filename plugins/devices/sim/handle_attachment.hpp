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

// A property of the operator's grasp from loose (grasp 0) to firm (1), geometric between: the values span two
// orders of magnitude and co-contraction raises them multiplicatively. Both ends above zero (the parameters'
// bounds).
struct GraspRange {
  double loose = 1.0;
  double firm = 1.0;
  [[nodiscard]] double at(double grasp) const noexcept { return loose * std::pow(firm / loose, grasp); }
};

struct AttachmentSettings {
  AttachmentKind kind = AttachmentKind::none;
  // Operator.
  double grasp = 0.5;  // 0 loose .. 1 firm
  double hand_mass_kg = 1.5;
  GraspRange grasp_stiffness{100.0, 30000.0};  // [N/m]
  GraspRange grasp_damping{2.0, 30.0};         // [N s/m]
  // Selected again with the same kind: keep the anchor, the hand's state and the profiles' clock (a move).
  bool keep_anchor = false;
  double arm_stiffness = 300.0;  // [N/m] towards the target motion
  double arm_damping = 25.0;     // [N s/m]
  Profile motion;                // target offset from the grasp position [m]
  Profile force;                 // voluntary force [N]
  // The same in rotation: the hand's rotational inertia held by the grasp's rotational spring-damper [loose,
  // firm] and pulled by the arm towards a target rotation.
  double hand_inertia_kg_m2 = 0.005;
  GraspRange grasp_rotational_stiffness{0.5, 50.0};  // [N m/rad]
  GraspRange grasp_rotational_damping{0.02, 0.5};    // [N m s/rad]
  double arm_rotational_stiffness = 5.0;             // [N m/rad] towards the target rotation
  double arm_rotational_damping = 0.2;               // [N m s/rad]
  Profile rotation;  // target rotation from the grasp orientation (rotation vector) [rad]
  Profile torque;    // voluntary torque [N m]
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

 private:
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
