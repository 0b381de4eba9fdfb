// The virtual coupling on the simulated ViSHaRD3 in lockstep: a rendering engine's proxy pose (published as
// the DDS interface will) pulls the device through the coupling spring; the operator pushing against a still
// proxy feels the coupling stiffness; a stale engine lets go of the device.
#include <gtest/gtest.h>

#include <cmath>

#include "hapticd/chain_state.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "session/device_requests.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;

std::string coupling_session(const std::string& push_n) {
  return "server: {clock: lockstep, seed: 7}\ndevices:\n" + test::sim_vishard3_device_yaml("v3", "constant", push_n) +
         R"(    virtual_model:
      plugin: admittance
      parameters: {mass_kg: [3.0, 3.0, 3.0], damping_n_s_per_m: [40.0, 40.0, 40.0], rotation: false,
                   coupling: true, coupling_stiffness_n_per_m: 2000, coupling_damping_n_s_per_m: 40}
    controller:
      plugin: resolved_acceleration
      parameters: {task: translation}
)";
}

// Runs 3 s; the engine publishes the proxy (start + offset) every cycle while publish(k) says so.
template <class Publish>
Eigen::Vector3d run(const std::string& push_n, const Eigen::Vector3d& offset, Publish publish,
                    Eigen::Vector3d* start_out = nullptr) {
  auto s = test::build_test_session(coupling_session(push_n));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  d.cycle(cycle_at(0), 1.0);
  const Eigen::Vector3d start = d.chain_state().handle_pose.position;
  if (start_out != nullptr) *start_out = start;
  EngineInput e;
  e.has_proxy = true;
  e.proxy_pose.position = start + offset;
  e.proxy_pose.orientation = d.chain_state().handle_pose.orientation;
  for (std::uint64_t k = 1; k < 6000; ++k) {
    if (publish(k)) {
      ++e.sequence;
      d.requests().engine_input(e);
    }
    d.cycle(cycle_at(k), 1.0);
    EXPECT_EQ(d.status().fault(), DeviceFault::none);
  }
  return d.chain_state().handle_pose.position - start;
}

TEST(VirtualCoupling, TheDeviceFollowsTheEnginesProxy) {
  const Eigen::Vector3d offset(0.03, -0.02, 0.0);
  const Eigen::Vector3d moved = run("[0.0, 0.0, 0.0]", offset, [](std::uint64_t) { return true; });
  std::printf("proxy 36 mm away: the handle ends %.2f mm from it\n", 1e3 * (moved - offset).norm());
  RecordProperty("proxy_following_error_mm", std::to_string(1e3 * (moved - offset).norm()));
  EXPECT_LT((moved - offset).norm(), 0.002);
}

TEST(VirtualCoupling, PushingAgainstAStillProxyFeelsTheCouplingSpring) {
  // 8 N against a proxy at the start position: the handle settles 8 N / 2000 N/m = 4 mm away.
  const Eigen::Vector3d moved = run("[8.0, 0.0, 0.0]", Eigen::Vector3d::Zero(), [](std::uint64_t) { return true; });
  std::printf("8 N against the proxy: %.2f mm (spring alone: 4.00 mm)\n", 1e3 * moved.x());
  RecordProperty("push_against_proxy_mm", std::to_string(1e3 * moved.x()));
  EXPECT_NEAR(moved.x(), 0.004, 0.0008);
}

TEST(VirtualCoupling, AStaleEngineLetsGoOfTheDevice) {
  // The operator pushes 8 N against the proxy; the engine falls silent after 1 s. 0.1 s later the coupling
  // fades out (over 0.2 s) and the push moves the device freely (virtual damping 40 N s/m: 0.2 m/s), instead
  // of an engine that no longer runs holding it 4 mm away.
  const Eigen::Vector3d moved =
      run("[8.0, 0.0, 0.0]", Eigen::Vector3d::Zero(), [](std::uint64_t k) { return k < 2000; });
  std::printf("engine silent from 1 s on: the pushed handle moved %.0f mm by 3 s\n", 1e3 * moved.x());
  EXPECT_GT(moved.x(), 0.1);
}

TEST(VirtualCoupling, RunTimeParametersTakeEffectAtTheNextCycle) {
  // The same 8 N push from rest, with the configured 3 kg and after setting 6 kg at run time (the DDS
  // request path): with 40 N s/m of damping the virtual speed after 100 ms is (F/b)(1 - exp(-t b/m)) for the
  // mass in effect. Bad values are refused.
  const auto moved_after_100ms = [](const std::vector<double>* mass) {
    auto s = test::build_test_session(coupling_session("[8.0, 0.0, 0.0]"));
    DeviceSession& d = *s.impl().devices[0];
    if (mass != nullptr) {
      EXPECT_TRUE(d.requests().apply({DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", *mass}).accepted);
    }
    EXPECT_FALSE(
        d.requests().apply({DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", {1.0, -1.0, 1.0}}).accepted);
    EXPECT_FALSE(
        d.requests().apply({DeviceRequest::Kind::set_parameter, "virtual_model.no_such_parameter", {1.0}}).accepted);
    EXPECT_FALSE(
        d.requests().apply({DeviceRequest::Kind::set_parameter, "controller.mass_kg", {1.0, 1.0, 1.0}}).accepted);
    d.activate();
    for (std::uint64_t k = 0; k <= 200; ++k) d.cycle(cycle_at(k), 1.0);
    return d.task().twist.linear.x();
  };
  const std::vector<double> six{6.0, 6.0, 6.0};
  const double v3 = moved_after_100ms(nullptr);
  const double v6 = moved_after_100ms(&six);
  std::printf("virtual speed after 100 ms of 8 N: 3 kg %.4f m/s, 6 kg (set at run time) %.4f m/s\n", v3, v6);
  EXPECT_NEAR(v3, 0.2 * (1.0 - std::exp(-0.1 * 40.0 / 3.0)), 0.004);
  EXPECT_NEAR(v6, 0.2 * (1.0 - std::exp(-0.1 * 40.0 / 6.0)), 0.004);
}

TEST(VirtualCoupling, CoupledUpdatesDoNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  auto s = test::build_test_session(coupling_session("[4.0, 0.0, 0.0]"));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  d.cycle(cycle_at(0), 1.0);
  EngineInput e;
  e.has_proxy = true;
  e.proxy_pose = d.chain_state().handle_pose;
  std::size_t allocations = 0;
  for (std::uint64_t k = 1; k < 2000; ++k) {
    if (k < 1000) d.requests().engine_input(e);  // the publisher side is not the loop: not counted below
    allocations += testing::count_allocations([&] { d.cycle(cycle_at(k), 1.0); });
  }
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace hapticd::server
