#pragma once
// The repulsion between two arms of a group (docs/multi-device.md), computed in the group stage: below
// `distance_m` of clearance a spring-damper on the clearance pushes the nearest points apart. Each device feels
// it on its handle, with the safety supervisor's own force (walls, speed damping): the handle force whose joint
// torques come closest to those of the force at the nearest point (the same for an arm whose handle position
// fixes its posture, as the ViSHaRD3's). Every pair of capsules within the distance adds its own. Real-time safe.
#include <Eigen/Core>

#include "config/repulsion_settings.hpp"
#include "hapticd/joint_vector.hpp"

namespace hapticd {
struct ChainState;
}

namespace hapticd::server {

// The force pushing the nearest points apart (N, along the clearance's normal): k (distance_m - d) - b d',
// never pulling (>= 0), zero at or beyond distance_m. `clearance_rate`: d', m/s.
[[nodiscard]] double repulsion_magnitude(const RepulsionSettings& settings, double clearance,
                                         double clearance_rate) noexcept;

// The handle force (world) for joint torques `torque`: the least-squares solution of J^T F = torque through the
// linear rows of the handle's Jacobian (chain.data), capped at max_force_n. Zero without a robot model.
[[nodiscard]] Eigen::Vector3d equivalent_handle_force(const ChainState& chain, const JointVector& torque,
                                                      double max_force_n) noexcept;

}  // namespace hapticd::server
