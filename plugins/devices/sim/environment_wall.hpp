#pragma once
// A wall in the simulated device's world: a plane at `offset_m` along `normal` from where the handle is when the
// device is enabled, pushing the handle back with a unilateral spring-damper (it pushes, never pulls) while the
// handle is beyond it. It acts on the handle besides the attachment, so the force sensor measures it: the remote
// environment of a simulated telemanipulator (docs/teleoperation.md). Real-time safe.
#include <Eigen/Core>
#include <algorithm>

namespace hapticd::sim {

struct WallSettings {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, towards the wall; zero: no wall
  double offset_m = 0.03;
  double stiffness = 5000.0;  // [N/m]
  double damping = 20.0;      // [N s/m]
};

class EnvironmentWall {
 public:
  void configure(const WallSettings& settings) noexcept { settings_ = settings; }
  [[nodiscard]] bool present() const noexcept { return settings_.normal.squaredNorm() > 0.0; }
  // The wall's plane is placed from the handle's position at the next force() after reset().
  void reset() noexcept { placed_ = false; }

  // The force on the handle at `position` moving at `velocity` (world).
  [[nodiscard]] Eigen::Vector3d force(const Eigen::Vector3d& position, const Eigen::Vector3d& velocity) noexcept {
    if (!present()) return Eigen::Vector3d::Zero();
    if (!placed_) {
      placed_ = true;
      origin_ = position;
    }
    const Eigen::Vector3d& n = settings_.normal;
    const double depth = n.dot(position - origin_) - settings_.offset_m;
    if (depth <= 0.0) return Eigen::Vector3d::Zero();
    const double push = std::max(0.0, settings_.stiffness * depth + settings_.damping * n.dot(velocity));
    return -push * n;
  }

 private:
  WallSettings settings_;
  bool placed_ = false;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::sim
