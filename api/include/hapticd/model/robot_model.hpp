#pragma once
// The immutable robot model: a serial chain of up to kMaxJoints revolute or prismatic joints, built once
// from a URDF (load_robot_model in urdf_loader.hpp) and shared by every algorithm and thread. Everything
// that changes per cycle lives in ModelData (model_data.hpp). Pattern: Pinocchio's model/data split.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/export.hpp"
#include "hapticd/joint_vector.hpp"
#include "hapticd/model/collision.hpp"
#include "hapticd/model/drive_data.hpp"

namespace hapticd::model {

enum class JointType { revolute, prismatic };

// One movable joint and the rigid body it moves (the URDF child link with every link fixed to it merged in).
struct Body {
  std::string joint_name;
  std::string link_name;
  JointType type = JointType::revolute;
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();  // joint frame in the parent body's frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();              // unit joint axis in the joint frame
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      // centre of mass in the body (joint) frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the centre of mass, body frame
  double position_min = -1e9;                         // [rad or m]; +-1e9: unlimited
  double position_max = 1e9;
  double velocity_limit = 0.0;  // URDF <limit velocity>, 0 if absent
  double effort_limit = 0.0;    // URDF <limit effort>, 0 if absent
  DriveData drive;
  double reflected_inertia = 0.0;  // drive inertia on the joint axis
};

// A named frame rigidly attached to a body (body -1: the fixed base).
struct Frame {
  std::string name;
  int body = -1;
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();  // in the body's joint frame
  // What the frame's link carries rigidly: its own mass and that of the links below it through fixed joints
  // (not through movable ones), centre of mass in this frame. For a force sensor's frame, the mass whose weight
  // and inertial force the sensor reads besides the external wrench (a handle, a gimbal).
  double carried_mass = 0.0;
  Eigen::Vector3d carried_com = Eigen::Vector3d::Zero();
};

class HAPTICD_API RobotModel {
 public:
  RobotModel(std::string name, std::string source_file, std::vector<Body> bodies, std::vector<Frame> frames,
             Eigen::Vector3d gravity);

  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] const std::string& source_file() const noexcept { return source_file_; }
  [[nodiscard]] int dof() const noexcept { return static_cast<int>(bodies_.size()); }
  [[nodiscard]] const Body& body(int i) const { return bodies_[static_cast<std::size_t>(i)]; }
  [[nodiscard]] const std::vector<Body>& bodies() const noexcept { return bodies_; }
  [[nodiscard]] const std::vector<Frame>& frames() const noexcept { return frames_; }
  [[nodiscard]] const Frame& frame(int id) const { return frames_[static_cast<std::size_t>(id)]; }
  // Index of a frame by name (every link is a frame, so are the named sensor and handle frames); -1 if absent.
  [[nodiscard]] int frame_id(std::string_view frame_name) const noexcept;
  // Like frame_id, but throws std::invalid_argument listing the known frames.
  [[nodiscard]] int require_frame(std::string_view frame_name) const;
  // Gravitational acceleration in the world frame (default (0, 0, -9.81)).
  [[nodiscard]] const Eigen::Vector3d& gravity() const noexcept { return gravity_; }
  // A copy with another gravity vector (for example zero, for free-motion tests).
  [[nodiscard]] RobotModel with_gravity(const Eigen::Vector3d& gravity) const;
  // A copy mounted at `base` (the URDF root's pose in the world frame): every pose, Jacobian and wrench the
  // model computes is then in the world frame, and gravity (a world vector) acts on the mounted device as it
  // would on the real one (a device hung upside down feels it reversed in its joints).
  [[nodiscard]] RobotModel with_base(const Eigen::Isometry3d& base) const;
  // The collision geometry (hapticd/model/collision.hpp): the URDF's <collision> elements as capsules.
  [[nodiscard]] const std::vector<Capsule>& collision() const noexcept { return capsules_; }
  // A copy with other collision geometry (at most PlacedCapsules::kMax capsules; throws std::invalid_argument
  // for more, a body the model does not have or a negative radius). Capsules on the base (body -1) are in the
  // model's root frame: give them before with_base, which carries them along.
  [[nodiscard]] RobotModel with_collision(std::vector<Capsule> capsules) const;
  // Joint-output peak torque per joint: the drive's, else the URDF effort limit, else 0.
  [[nodiscard]] JointVector peak_torques() const;
  // Joint speed limit per joint: the drive's, else the URDF velocity limit, else 0.
  [[nodiscard]] JointVector speed_limits() const;
  // Reflected drive inertia per joint.
  [[nodiscard]] JointVector reflected_inertias() const;

 private:
  std::string name_;
  std::string source_file_;
  std::vector<Body> bodies_;
  std::vector<Frame> frames_;
  Eigen::Vector3d gravity_;
  std::vector<Capsule> capsules_;
};

}  // namespace hapticd::model
