#pragma once
// The simulated devices' physics (FlexibleChain) built from a shipped device model, for the physics tests.
#include <cstdint>

#include "physics_builder.hpp"
#include "support/device_models.hpp"

namespace hapticd::test {

inline constexpr double kSubstepS = 1.0 / 20000.0;  // the sim plugin's default substep

// The chain of a device model (test::kDeviceModels), its rigid-body terms every `rigid_body_every` substeps
// (1: the single-rate integrator).
inline sim::FlexibleChain make_chain(const char* device, const sim::PhysicsOptions& options, std::uint64_t seed = 1,
                                     int rigid_body_every = 1) {
  const model::RobotModel robot = load_device_model(device);
  sim::FlexibleChain chain = sim::build_flexible_chain(robot, robot.require_frame("handle"), options, seed);
  chain.set_rigid_body_every(rigid_body_every);
  return chain;
}

// No friction, ripple or structural damping: energy is conserved.
inline sim::PhysicsOptions lossless() {
  sim::PhysicsOptions o;
  o.friction = false;
  o.ripple = false;
  o.damping_ratio = 0.0;
  return o;
}

}  // namespace hapticd::test
