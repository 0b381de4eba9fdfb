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

struct ChainState {
  // Null when the device names no robot model (the plugins then work from DeviceState alone).
  const model::RobotModel* model = nullptr;
  // compute_cycle_terms at (q, qd) - the input's DeviceState positions and its one velocity estimate - for the
  // handle frame: frame_pose, frame_jacobian (6 x n, rows
  // [linear; angular]), frame_jacobian_dot_qd, mass_matrix (+ mass_llt), coriolis_torque, gravity_torque.
  const model::ModelData* data = nullptr;
  int handle_frame = -1;
  Pose handle_pose;                  // world
  Twist handle_twist;                // world, at the handle point
  Wrench operator_wrench;            // world, at the handle point: the wrench the operator applies TO the handle
  bool has_operator_wrench = false;  // the device has a force/torque sensor
  bool output_saturated = false;     // the previous cycle's torque command was clamped at a drive's peak torque
};

}  // namespace hapticd
