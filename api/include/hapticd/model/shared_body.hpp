#pragma once
// The shared virtual object of bimanual coupling (docs/multi-device.md, "Bimanual coupling"): one rigid box that
// several hands hold at once. Each hand is coupled to its grasp point on the box by a spring-damper (the virtual
// coupling); the box has mass and inertia (a solid box), falls under gravity and rests on a table plane
// (penalty contact at its corners with viscous-regularised Coulomb friction). Integrated at the loop rate in
// substeps (semi-implicit Euler); each step answers the force every hand feels. Allocates nothing after
// configure(); real-time safe.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <span>

#include "hapticd/export.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd::model {

struct SharedBodySettings {
  double mass_kg = 1.0;
  Eigen::Vector3d size_m{0.30, 0.15, 0.10};  // edge lengths along the body's x, y, z (its inertia: a solid box)
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};  // world
  double coupling_stiffness_n_per_m = 2000.0;
  double coupling_damping_n_s_per_m = 20.0;
  bool table = true;
  double table_height_m = 0.0;               // the plane z = height (world), its normal +z
  double table_stiffness_n_per_m = 20000.0;  // per corner in contact
  double table_damping_n_s_per_m = 200.0;
  double table_friction = 0.6;        // Coulomb coefficient
  double friction_speed_m_s = 0.002;  // below this sliding speed friction grows linearly (regularised)
  int substeps = 4;                   // per loop period
};

class HAPTICD_API SharedBody {
 public:
  static constexpr std::size_t kMaxHands = 8;

  // period_s: the loop's. Throws std::invalid_argument on a non-positive mass, size or period.
  void configure(const SharedBodySettings& settings, double period_s);
  // The body at rest at `pose` (world), hand k attached at grasp[k] (body frame).
  void reset(const Pose& pose, std::span<const Eigen::Vector3d> grasp);

  // One loop period: the hands' positions and velocities (world) -> the force on each hand (world). Hands beyond
  // the grasp points given to reset() are ignored (their force zero).
  void step(std::span<const Eigen::Vector3d> hand_position, std::span<const Eigen::Vector3d> hand_velocity,
            std::span<Eigen::Vector3d> hand_force) noexcept;

  [[nodiscard]] const Eigen::Vector3d& position() const noexcept { return position_; }
  [[nodiscard]] const Eigen::Quaterniond& orientation() const noexcept { return orientation_; }
  [[nodiscard]] const Eigen::Vector3d& velocity() const noexcept { return velocity_; }
  [[nodiscard]] const Eigen::Vector3d& angular_velocity() const noexcept { return angular_velocity_; }
  // The grasp point of hand k, world.
  [[nodiscard]] Eigen::Vector3d grasp_point(std::size_t k) const noexcept {
    return position_ + orientation_ * grasp_[k];
  }
  // The force hand k exerts on the body (world), at the end of the last step.
  [[nodiscard]] const Eigen::Vector3d& hand_force_on_body(std::size_t k) const noexcept { return on_body_[k]; }
  // The squeeze between hands 0 and 1 along the line joining their grasp points (N; positive compresses the
  // body, negative pulls it apart): the part of their forces that cancels, (F0 - F1) . u / 2 with u from grasp 0
  // to grasp 1.
  [[nodiscard]] double internal_force_n() const noexcept;
  // The table's force on the body (world), at the end of the last step.
  [[nodiscard]] const Eigen::Vector3d& table_force() const noexcept { return table_force_; }

 private:
  void substep(double dt, std::span<const Eigen::Vector3d> hand_position,
               std::span<const Eigen::Vector3d> hand_velocity) noexcept;

  SharedBodySettings settings_;
  double period_s_ = 0.0;
  Eigen::Matrix3d inertia_body_ = Eigen::Matrix3d::Identity();
  std::array<Eigen::Vector3d, 8> corners_{};  // body frame
  std::array<Eigen::Vector3d, kMaxHands> grasp_{};
  std::array<Eigen::Vector3d, kMaxHands> on_body_{};
  std::size_t hands_ = 0;
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_ = Eigen::Vector3d::Zero();  // world
  Eigen::Vector3d table_force_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::model
