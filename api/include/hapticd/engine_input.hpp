#pragma once
// What an external rendering engine last sent for a device (the DDS interface writes it; the server hands
// the newest one to the virtual model each cycle). Fixed-size: copying it never allocates.
//   - an impedance-type engine sends a proxy pose (the "god object" its virtual world allows) that the
//     virtual coupling ties the device to, or a wrench to display directly, optionally with a local linear
//     model (stiffness and damping about an anchor pose) the virtual model evaluates every cycle until the
//     engine's next update;
//   - an admittance-type engine sends the desired motion of the handle.
// The server owns staleness: `weight` is 1 while the engine keeps its deadline and falls linearly to 0 over
// the fade time after a missed deadline (and is 0 before the first input). Virtual models scale everything
// they take from the engine by it, so a stalled or disconnected engine lets go of the device smoothly.
#include <Eigen/Core>
#include <cstdint>

#include "hapticd/spatial.hpp"

namespace hapticd {

struct EngineInput {
  // Impedance type: proxy pose and twist for the virtual coupling.
  Pose proxy_pose;
  Twist proxy_twist;
  bool has_proxy = false;
  // Impedance type: the wrench the engine's world applies to the handle (world axes, at the handle point),
  // plus, with has_local_model, stiffness .* (anchor - x) - damping .* xd evaluated by the virtual model.
  Wrench wrench;
  bool has_wrench = false;
  bool has_local_model = false;
  Pose anchor;
  Eigen::Matrix<double, 6, 1> stiffness = Eigen::Matrix<double, 6, 1>::Zero();  // N/m x3, N m/rad x3
  Eigen::Matrix<double, 6, 1> damping = Eigen::Matrix<double, 6, 1>::Zero();    // N s/m x3, N m s/rad x3
  // Admittance type: the desired motion of the handle.
  Pose motion_pose;
  Twist motion_twist;
  bool has_motion = false;

  std::int64_t received_ns = 0;  // loop time at which the loop picked it up
  std::uint64_t sequence = 0;    // the engine's serial number
  double weight = 0.0;           // set by the server every cycle (see above)
};

}  // namespace hapticd
