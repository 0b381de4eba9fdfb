#pragma once
// A MuJoCo world coupled to haptic devices (docs/engines.md, "Physics engines"). For each device the scene has a
// proxy: a free body named `proxy_<device>` (or `proxy` when the world couples one device). Every state period
// the world takes each device's hand (the pose and twist its state gives), pulls the proxy towards it with the
// virtual coupling's spring-damper - the same stiffness and damping the server renders on the device, so the
// two sides feel equal and opposite forces - and steps MuJoCo a fixed number of times; the engine then sends
// the proxy's pose and twist back as a COUPLING command. The proxy's weight is compensated: in free space it
// follows the hand with nothing to feel.
//
// Nothing here knows DDS: hapticd-mujoco-engine feeds it from the client library, the lockstep tests from
// the in-process session. The scene's frame is placed in the server's world frame by `scene_to_world`.
// Threads: one thread at a time (the engine's state callback, or a test).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/spatial.hpp"

namespace hapticd::mujoco {

// A scene that does not load or does not fit: the message is MuJoCo's (with the MJCF line) or names what is missing.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The coupling's spring-damper, as the device's virtual model renders it (its parameters
// virtual_model.coupling_*). Rotational stiffness 0: the device does not couple rotation; the world then holds the
// proxy at the orientation the scene gives it (a peg stays upright whatever the handle's gimbal does), and the
// device feels no torque.
struct CouplingGains {
  double stiffness_n_per_m = 2000.0;
  double damping_n_s_per_m = 20.0;
  double rotational_stiffness_n_m_per_rad = 0.0;
  double rotational_damping_n_m_s = 0.0;
};

// A device's side of the coupling (server world frame).
struct Hand {
  Pose pose;
  Twist twist;
};

// A proxy after a step (server world frame).
struct Proxy {
  Pose pose;
  Twist twist;
  Eigen::Vector3d contact_force = Eigen::Vector3d::Zero();   // what the scene's contacts apply to the proxy
  Eigen::Vector3d coupling_force = Eigen::Vector3d::Zero();  // what the coupling applies to the proxy
};

// One geometry of the scene, for a viewer (server world frame).
struct BodyShape {
  std::string body;
  std::string type;  // "plane", "sphere", "capsule", "ellipsoid", "cylinder", "box"; meshes and heightfields as "box"
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // MuJoCo's geom size (half-extents, radius, half-length)
  Eigen::Vector4f rgba = Eigen::Vector4f::Ones();
  Pose pose;
};

// A capsule of a device's arm (server world frame): the segment a-b and its radius.
struct ArmCapsule {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  double radius = 0.0;
};

struct WorldOptions {
  std::filesystem::path scene;       // an MJCF file
  std::vector<std::string> devices;  // one proxy each, in this order
  // The devices' state period. The world steps period/substeps at a time, substeps = round(period / the MJCF's
  // timestep), at least 1: fixed, so a run in lockstep repeats exactly.
  double state_period_s = 1e-3;
  Eigen::Isometry3d scene_to_world = Eigen::Isometry3d::Identity();
};

struct StepReport {
  // false: the world went unstable (a coupling or contact too stiff for the step): MuJoCo found a bad acceleration
  // and reset the world to its initial state, or a proxy ran away (faster than 3 m/s). The proxies were put back at
  // the hands, at rest - no jump and no pull for the hands - and the step ended there. Stop rendering with it.
  bool stable = true;
};

class CoupledWorld {
 public:
  // Throws SceneError: the file does not load (MuJoCo's message), a device has no proxy body, a proxy is not a
  // free body of its own (one free joint, no child bodies).
  explicit CoupledWorld(const WorldOptions& options);
  ~CoupledWorld();
  CoupledWorld(const CoupledWorld&) = delete;
  CoupledWorld& operator=(const CoupledWorld&) = delete;

  [[nodiscard]] std::size_t device_count() const noexcept;
  [[nodiscard]] const std::string& device(std::size_t i) const;
  [[nodiscard]] int substeps() const noexcept;
  [[nodiscard]] double timestep_s() const noexcept;
  [[nodiscard]] double time_s() const noexcept;
  [[nodiscard]] const Eigen::Isometry3d& scene_to_world() const noexcept;

  // Throws SceneError when the physics step cannot resolve the coupling at the proxy's mass and inertia (the message
  // says what to change).
  void set_gains(std::size_t device, const CouplingGains& gains);
  [[nodiscard]] const CouplingGains& gains(std::size_t device) const;
  // Puts a proxy at its hand, at rest (at the start, and when the engine claims a device again); set the gains first.
  void place(std::size_t device, const Hand& hand);

  // The device's arm in the scene (optional per scene): the scene's mocap bodies `arm_<device>_<k>` (or `arm_<k>`
  // when it couples one device), each with one capsule geom, k = 0, 1, ..., take the device's capsules - their
  // poses and sizes - so that the arm itself pushes the scene's objects (kinematic: nothing pushes it back).
  // Bodies beyond the capsules given are parked out of reach. A device's arm never touches its own proxy (the world
  // sets the collision bits of the proxies' and arms' geoms in such scenes: contype/conaffinity bit 0 is for
  // everything else). No allocation.
  void set_arm(std::size_t device, std::span<const ArmCapsule> capsules) noexcept;
  // How many arm bodies the scene has for the device (0: it shows no arm).
  [[nodiscard]] std::size_t arm_bodies(std::size_t device) const noexcept;

  // Advances the world `periods` state periods (substeps each) with the hands (one per device, in order) held.
  // No allocation.
  StepReport step(std::span<const Hand> hands, int periods = 1) noexcept;

  [[nodiscard]] Proxy proxy(std::size_t device) const noexcept;
  // A body's pose (server world frame); empty for a name the scene does not have.
  [[nodiscard]] std::optional<Pose> body_pose(std::string_view body) const;
  [[nodiscard]] std::optional<Twist> body_twist(std::string_view body) const;
  // Every geometry of the scene with its pose now.
  [[nodiscard]] std::vector<BodyShape> shapes() const;
  // The energy the coupling has given the proxies since the start (J): integrated force times proxy velocity.
  [[nodiscard]] double coupling_work_j() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A device's arm as capsules for CoupledWorld::set_arm: its robot model (URDF; its <collision> capsules, else
// capsules of `radius` along its kinematic skeleton), placed at the device's base pose.
class ArmModel {
 public:
  // Throws std::runtime_error for a model that does not load (the message says why).
  ArmModel(const std::filesystem::path& urdf, double radius, const Pose& base);
  ~ArmModel();
  ArmModel(ArmModel&&) noexcept;
  ArmModel& operator=(ArmModel&&) noexcept;
  [[nodiscard]] int dof() const noexcept;
  // The capsules at the joint positions `q` (at least dof() of them; the rest ignored). No allocation.
  [[nodiscard]] std::span<const ArmCapsule> place(std::span<const double> q) noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The scene frame of a set of devices: one device - its start position, the world's axes; more - the middle of
// their start positions, x horizontal from the first device's to the last one's, z up (the world's z).
[[nodiscard]] Eigen::Isometry3d scene_frame(std::span<const Eigen::Vector3d> start_positions);

}  // namespace hapticd::mujoco
