#pragma once
// What the server computes once per cycle for a device with a robot model, and every plugin of its chain
// reads (never writes): the model terms at the measured state, the handle's motion and the operator's wrench
// in the world frame. Computing them once keeps the chain cheap and consistent (everyone sees the same J).
#include "hapticd/joint_vector.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd {
namespace model {
class RobotModel;
struct ModelData;
}  // namespace model

// The nearest other device of the device's group this cycle, found in the group stage (docs/multi-device.md): a
// redundant arm's inverse kinematics may move away from it in its null space. Without a neighbour (no group, or a
// device without a robot model): distance 1e9 and an empty gradient.
struct NeighbourClearance {
  double distance_m = 1e9;                            // between the nearest capsules' surfaces; < 0: overlap
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // the closest point on this device, world
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  // unit, world: the way that point gains clearance
  JointVector gradient;                               // d distance_m / d q at the measured joints (n)
  [[nodiscard]] bool present() const noexcept { return gradient.size() > 0; }
};

struct ChainState {
  // Null when the device names no robot model (the plugins then work from DeviceState alone).
  const model::RobotModel* model = nullptr;
  // compute_cycle_terms at (q, qd) - the input's DeviceState positions and its one velocity estimate - for the
  // handle frame: frame_pose, frame_jacobian (6 x n, rows
  // [linear; angular]), frame_jacobian_dot_qd, mass_matrix (+ mass_llt), coriolis_torque, gravity_torque.
  const model::ModelData* data = nullptr;
  int handle_frame = -1;
  // The handle's pose and twist are known: from the robot model, or reported by a handle device (model null).
  bool has_handle = false;
  Pose handle_pose;                  // world
  Twist handle_twist;                // world, at the handle point
  Wrench operator_wrench;            // world, at the handle point: the wrench the operator applies TO the handle
  bool has_operator_wrench = false;  // the device has a force/torque sensor
  bool output_saturated = false;     // the previous cycle's torque command was clamped at a drive's peak torque
  NeighbourClearance neighbour;      // the group stage's, this cycle
};

}  // namespace hapticd
