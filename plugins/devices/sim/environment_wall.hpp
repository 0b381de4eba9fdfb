#pragma once
// A wall in the simulated device's world: a plane at `offset_m` along `normal` from where the handle is when the
// device is enabled, pushing the handle back with a unilateral spring-damper (it pushes, never pulls) while the
// handle is beyond it. It acts on the handle besides the attachment, so the force sensor measures it: the remote
// environment of a simulated telemanipulator (docs/teleoperation.md). The handle touches it at a point, or with
// `contact_half_width_m` with a square plate that turns with the handle (its face parallel to the wall at enable):
// four corners, each a quarter of the wall's spring-damper, so a tilted plate is turned back as well as pushed - a
// contact in six degrees of freedom. Real-time safe.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

namespace hapticd::sim {

struct WallSettings {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, towards the wall; zero: no wall
  double offset_m = 0.03;
  double stiffness = 5000.0;          // [N/m]
  double damping = 20.0;              // [N s/m]
  double contact_half_width_m = 0.0;  // 0: a point contact at the handle; else the plate's half width [m]
};

// The wall's force and torque on the handle (world, about the handle's point).
struct WallWrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
};

class EnvironmentWall {
 public:
  void configure(const WallSettings& settings) noexcept { settings_ = settings; }
  [[nodiscard]] bool present() const noexcept { return settings_.normal.squaredNorm() > 0.0; }
  // The wall's plane (and the plate's corners) are placed from the handle's pose at the next wrench() after reset().
  void reset() noexcept { placed_ = false; }

  // The wrench on the handle at `pose` moving at `linear` and `angular` velocity (world).
  [[nodiscard]] WallWrench wrench(const Eigen::Isometry3d& pose, const Eigen::Vector3d& linear,
                                  const Eigen::Vector3d& angular) noexcept {
    WallWrench w;
    if (!present()) return w;
    if (!placed_) place(pose);
    if (settings_.contact_half_width_m <= 0.0) {
      w.force = push(pose.translation(), linear, 1.0);
      return w;
    }
    // The corners turn with the handle: their offsets at enable, rotated by the handle's rotation since.
    const Eigen::Matrix3d turn = pose.linear() * start_rotation_.transpose();
    for (const Eigen::Vector3d& corner : corners_) {
      const Eigen::Vector3d r = turn * corner;
      const Eigen::Vector3d f = push(pose.translation() + r, linear + angular.cross(r), 0.25);
      w.force += f;
      w.torque += r.cross(f);
    }
    return w;
  }

 private:
  void place(const Eigen::Isometry3d& pose) noexcept {
    placed_ = true;
    origin_ = pose.translation();
    start_rotation_ = pose.linear();
    // Two directions in the wall's plane: the plate's edges.
    const Eigen::Vector3d& n = settings_.normal;
    const Eigen::Vector3d a =
        (std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(n).normalized();
    const Eigen::Vector3d b = n.cross(a);
    const double h = settings_.contact_half_width_m;
    corners_ = {h * (a + b), h * (a - b), h * (-a + b), h * (-a - b)};
  }
  // A point's push from the wall with `share` of its spring-damper.
  [[nodiscard]] Eigen::Vector3d push(const Eigen::Vector3d& point, const Eigen::Vector3d& velocity,
                                     double share) const noexcept {
    const Eigen::Vector3d& n = settings_.normal;
    const double depth = n.dot(point - origin_) - settings_.offset_m;
    if (depth <= 0.0) return Eigen::Vector3d::Zero();
    const double f = std::max(0.0, share * (settings_.stiffness * depth + settings_.damping * n.dot(velocity)));
    return -f * n;
  }

  WallSettings settings_;
  bool placed_ = false;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d start_rotation_ = Eigen::Matrix3d::Identity();
  std::array<Eigen::Vector3d, 4> corners_{};
};

}  // namespace hapticd::sim
