// Anti-windup of the virtual admittance at output saturation (conditional integration): while the drives
// saturate and the device cannot follow, the virtual body is held within max_tracking_error_m of the handle;
// without saturation, or without the limit, it moves on freely. Driven directly with a synthetic chain state
// (a device held still, an operator pushing 20 N) so that the saturation flag is under the test's control.
#include <gtest/gtest.h>

#include "hapticd/chain_state.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/testing/pass_through_render_port.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;

// Distance the virtual body gets from a handle held still after 1 s of a 20 N push.
double runaway(double limit_m, bool saturated) {
  const std::string yaml = "server: {clock: lockstep, seed: 7}\ndevices:\n" +
                           test::sim_vishard3_device_yaml("v3", "constant", "[0.0, 0.0, 0.0]") + R"(    virtual_model:
      plugin: admittance
      parameters: {mass_kg: [2.0, 2.0, 2.0], damping_n_s_per_m: [10.0, 10.0, 10.0], rotation: false,
                   max_tracking_error_m: )" +
                           std::to_string(limit_m) + R"(}
    controller:
      plugin: resolved_acceleration
      parameters: {task: translation}
)";
  auto s = test::build_test_session(yaml);
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  d.cycle(cycle_at(0), 1.0);  // a real chain state of the device (model, pose) to start from
  ChainState chain = d.chain_state();
  chain.operator_wrench.force = Eigen::Vector3d(20.0, 0.0, 0.0);
  chain.handle_twist = Twist{};
  chain.output_saturated = saturated;
  VirtualModel& model = **s.impl().devices[0]->chain().schemes[0].virtual_model;
  const EngineInput engine;
  testing::PassThroughRenderPort render;
  TaskTarget target;
  EXPECT_TRUE(model.activate(VirtualModelInput{d.state(), chain, engine, render}).ok());
  for (std::uint64_t k = 1; k <= 2000; ++k) {
    EXPECT_TRUE(model.update(cycle_at(k), VirtualModelInput{d.state(), chain, engine, render}, target).ok());
  }
  EXPECT_LE(target.twist.linear.x(), 1.0);
  return (target.pose.position - chain.handle_pose.position).norm();
}

TEST(AntiWindup, ASaturatedDeviceHoldsTheVirtualBodyWithinTheLimit) {
  const double saturated_limited = runaway(0.01, true);
  const double saturated_free = runaway(0.0, true);
  const double unsaturated_limited = runaway(0.01, false);
  std::printf(
      "virtual body ahead of a blocked handle after 1 s of 20 N: %.1f mm (saturated, 10 mm limit), "
      "%.0f mm (no limit), %.0f mm (limit, drives not saturated)\n",
      1e3 * saturated_limited, 1e3 * saturated_free, 1e3 * unsaturated_limited);
  EXPECT_NEAR(saturated_limited, 0.01, 1e-9);
  EXPECT_GT(saturated_free, 0.5);       // 20 N on 2 kg with 10 N s/m: well over a metre per second
  EXPECT_GT(unsaturated_limited, 0.5);  // the limit acts only while the drives saturate
}

}  // namespace
}  // namespace hapticd::server
