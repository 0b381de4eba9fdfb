#pragma once
// What an object of the haptic scene feels like (docs/haptic-scene.md, "Materials"): the stiffness and damping of
// its surface, its Coulomb friction (static and dynamic: the proxy sticks until the tangential force passes the
// static limit, then slides against the dynamic one), and a texture - a solid sinusoidal relief in the object's
// frame, felt as a ripple of the normal force at its spatial period on every contact.
#include <Eigen/Core>
#include <cmath>
#include <numbers>

namespace hapticd::scene {

struct Material {
  double stiffness_n_per_m = 2000.0;
  double damping_n_s_per_m = 5.0;    // on the hand's velocity into the surface, only while in contact
  double static_friction = 0.0;      // coefficient
  double dynamic_friction = 0.0;     // coefficient, at most the static one
  double texture_amplitude_m = 0.0;  // the relief's height: the normal force ripples by stiffness x this
  double texture_period_m = 0.002;   // the relief's spatial period
};

// The relief's height at a point of the surface (object frame): amplitude x the mean of three cosines, one per
// axis, so every face of every shape ripples along both of its directions at the period.
[[nodiscard]] inline double texture_height(const Material& m, const Eigen::Vector3d& local_point) noexcept {
  if (m.texture_amplitude_m == 0.0) return 0.0;
  const double w = 2.0 * std::numbers::pi / m.texture_period_m;
  return m.texture_amplitude_m *
         (std::cos(w * local_point.x()) + std::cos(w * local_point.y()) + std::cos(w * local_point.z())) / 3.0;
}

}  // namespace hapticd::scene
