#pragma once
// Builds a FlexibleChain from a robot model with drive data: springs from the stiffness range, reflected
// motor inertia, the structure's series compliance, structural damping, friction with per-joint variation and ripple
// (seeded).
#include "flexible_chain.hpp"

namespace hapticd::sim {

struct PhysicsOptions {
  // Damping ratio of each drive spring (on the motor inertia); below 0: the model's (DriveData::damping_ratio)
  // where it gives one, else kDefaultDampingRatio.
  static constexpr double kDefaultDampingRatio = 0.02;
  double damping_ratio = -1.0;
  double friction_variation = 0.1;       // relative standard deviation of the per-joint friction scale
  bool friction = true;                  // master switch of all friction effects
  FrictionParameters friction_template;  // switches and curves shared by the joints
  bool ripple = true;
  // The structure's compliance in series with each gear (DriveData::structural_stiffness, where the model gives
  // one): the joint's spring is the series combination (docs/simulated-devices.md).
  bool structural_compliance = true;
  double ripple_min_nm = 0.12, ripple_max_nm = 0.19;
};

// Throws std::invalid_argument when a joint has no drive data.
[[nodiscard]] FlexibleChain build_flexible_chain(const model::RobotModel& model, int handle_frame,
                                                 const PhysicsOptions& options, std::uint64_t seed);

}  // namespace hapticd::sim
