// Device groups (`groups`): the group stage measures the clearance between the group's devices every cycle, in the
// world frame; below the group's hard minimum both devices of the pair enter their safe mode with a fault naming
// the pair and the links, and devices outside the group run on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "assembly/session_impl.hpp"
#include "hapticd/model/collision.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/server/session.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

// A simulated ViSHaRD3 at `base` in admittance display (3 kg, 40 N s/m), pushed from 0.1 s on by `force`.
std::string vishard3(const std::string& name, const std::string& base, const std::string& force) {
  return test::sim_vishard3_device_yaml(name, "step", force) + "        wrench_force_start_s: 0.1\n" +
         "    base_pose: " + base + "\n" + test::vishard3_admittance_chain_yaml();
}

// Two ViSHaRD3 facing each other 0.9 m apart along x (the right one turned half a turn), their handles pushed
// towards each other by `force_n` each; a third device on its own beside them. `group_extra`: more keys of the
// group (indented 4).
std::string facing_pair(const std::string& force_n, double min_distance_m, const std::string& group_extra = "") {
  return "server: {clock: lockstep, seed: 5}\ndevices:\n" +
         vishard3("left", "{xyz: [0, 0, 0]}", "[" + force_n + ", 0, 0]") +
         vishard3("right", "{xyz: [0.9, 0, 0], rpy: [0, 0, 3.141592653589793]}", "[-" + force_n + ", 0, 0]") +
         vishard3("alone", "{xyz: [0, 2, 0]}", "[0, 0, 0]") +
         "groups:\n  - name: hands\n    devices: [left, right]\n    min_distance_m: " + std::to_string(min_distance_m) +
         "\n" + group_extra;
}

const CollisionGuard& guard_of(Session& s) { return *s.impl().stages.at(0)->guards().at(0); }

TEST(DeviceGroups, TheGroupStageMeasuresTheClearanceInTheWorldFrame) {
  Session s = test::build_test_session(facing_pair("0", 0.0));
  s.step(1);
  const CollisionGuard& guard = guard_of(s);
  // Independently: both models mounted where the session puts them, at the measured joints.
  double expected = 1e9;
  {
    const auto& a = *s.impl().device("left").chain().robot_model;
    const auto& b = *s.impl().device("right").chain().robot_model;
    model::ModelData da(a), db(b);
    model::forward_kinematics(a, da, s.device("left").state.joints.position);
    model::forward_kinematics(b, db, s.device("right").state.joints.position);
    model::PlacedCapsules pa, pb;
    model::place_capsules(a, da, pa);
    model::place_capsules(b, db, pb);
    expected = model::nearest(pa, pb).distance;
  }
  EXPECT_NEAR(guard.latest_distance(), expected, 1e-12);
  EXPECT_GT(guard.latest_distance(), 0.05) << "the pair must start apart for the next tests";
  EXPECT_LT(guard.latest_distance(), 0.6);
  EXPECT_TRUE(s.impl().stages.at(0)->guards().size() == 1u);
}

TEST(DeviceGroups, BelowTheHardMinimumBothDevicesOfThePairStopAndOthersRunOn) {
  Session s = test::build_test_session(facing_pair("20", 0.03));
  const CollisionGuard& guard = guard_of(s);
  double before_trip = 1e9;
  for (int k = 0; k < 4000 && s.device("left").fault.empty(); ++k) {
    s.step(1);
    if (s.device("left").fault.empty()) before_trip = guard.latest_distance();
  }
  const DeviceView left = s.device("left");
  const DeviceView right = s.device("right");
  ASSERT_FALSE(left.fault.empty()) << "the pushed arms never came within the minimum (closest "
                                   << guard.smallest_distance() << " m)";
  EXPECT_NE(left.fault.find("too close: left "), std::string::npos) << left.fault;
  EXPECT_NE(left.fault.find(" / right "), std::string::npos) << left.fault;
  EXPECT_EQ(right.fault, left.fault);
  EXPECT_GE(before_trip, 0.03);
  EXPECT_LT(guard.latest_distance(), 0.03);
  EXPECT_EQ(guard.trips(), 1u);
  EXPECT_EQ(s.impl().device("left").status().fault(), DeviceFault::collision);
  // The third device is not in the group: it runs on.
  s.step(200);
  EXPECT_TRUE(s.device("alone").fault.empty()) << s.device("alone").fault;
  // A recovery while the arms are still too close trips again at once: the operators must part them first.
  ASSERT_TRUE(s.request("left", {DeviceRequest::Kind::recover, "", {}}).accepted);
  s.step(2000);
  EXPECT_FALSE(s.device("left").fault.empty());
}

TEST(DeviceGroups, WithoutAMinimumNothingTrips) {
  Session s = test::build_test_session(facing_pair("8", 0.0));
  const CollisionGuard& guard = guard_of(s);
  for (int k = 0; k < 6000 && guard.smallest_distance() >= 0.03; ++k) s.step(1);
  EXPECT_LT(guard.smallest_distance(), 0.03) << "the arms must come closer than the minimum of the test above";
  EXPECT_EQ(guard.trips(), 0u);
  EXPECT_TRUE(s.device("left").fault.empty()) << s.device("left").fault;
  EXPECT_TRUE(s.device("right").fault.empty()) << s.device("right").fault;
}

TEST(DeviceGroups, TheRepulsionKeepsThePairApartAndTheOperatorsFeelIt) {
  // The push that brings the arms within 0.03 m without repulsion (the test above), now against the repulsion
  // from 0.1 m: the arms settle where the springs between their links hold the push, the hard minimum never trips,
  // and each handle renders the force that balances its operator's push - steadily (the torques' low-pass keeps
  // the jumps of the closest points along nearly parallel links out of it).
  Session s = test::build_test_session(
      facing_pair("8", 0.03, "    repulsion: {distance_m: 0.1, stiffness_n_per_m: 1000, damping_n_s_per_m: 20}\n"));
  const CollisionGuard& guard = guard_of(s);
  s.step(5000);  // 2.5 s: the arms meet at about 2 s
  double sum = 0.0, squares = 0.0, speed = 0.0;
  constexpr int kCycles = 1000;
  for (int k = 0; k < kCycles; ++k) {
    s.step(1);
    const double f = s.device("left").task.wrench.force.x();
    sum += f;
    squares += f * f;
    speed = std::max(speed, std::abs(s.device("left").handle_twist.linear.x()));
  }
  const double mean = sum / kCycles;
  EXPECT_EQ(guard.trips(), 0u);
  EXPECT_TRUE(s.device("left").fault.empty()) << s.device("left").fault;
  EXPECT_TRUE(s.device("right").fault.empty()) << s.device("right").fault;
  EXPECT_GT(guard.smallest_distance(), 0.07);
  EXPECT_LT(guard.latest_distance(), 0.1) << "the push must hold the arms inside the repulsion";
  EXPECT_GT(guard.latest_repulsion_n(), 8.0);
  EXPECT_NEAR(mean, -8.0, 0.3) << "the left handle renders what holds its operator's push along x";
  EXPECT_LT(std::sqrt(squares / kCycles - mean * mean), 0.6) << "the rendered force must be steady";
  EXPECT_LT(speed, 0.02) << "the handles must have stopped approaching";
}

TEST(DeviceGroups, TheGroupStageAndItsSnapshotDoNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  Session s = test::build_test_session(facing_pair("8", 0.03, "    repulsion: {distance_m: 0.9}\n"));
  s.step(10);  // powered, the chains active
  LoopCycle& cycle = *s.impl().cycle;
  s.impl().stages.at(0)->set_snapshot_interval(1);  // and its snapshot of the devices' (the DDS group state)
  for (const auto& d : s.impl().devices) d->set_snapshot_interval(1);
  testing::AllocationGuard guard;
  for (std::uint64_t k = 10; k < 1010; ++k) cycle.run_cycle(test::cycle_at(k), 1.0, 0, 0);
  EXPECT_EQ(guard.allocations(), 0u);
  auto snapshot = std::make_unique<GroupSnapshot>();
  ASSERT_TRUE(s.impl().stages.at(0)->take_snapshot(*snapshot));
  EXPECT_EQ(snapshot->cycle, 1009u);
  ASSERT_EQ(snapshot->count, 2u);
  EXPECT_EQ(snapshot->devices[0].cycle, 1009u);
  EXPECT_EQ(snapshot->devices[1].cycle, 1009u);
  EXPECT_GT(snapshot->clearance_m, 0.0);
  EXPECT_LT(guard_of(s).latest_distance(), 1.0);     // the guards ran
  EXPECT_GT(guard_of(s).latest_repulsion_n(), 0.0);  // and repelled
}

TEST(DeviceGroups, AreCheckedInTheSessionFile) {
  const auto error_of = [](const std::string& groups) {
    try {
      (void)test::build_test_session("server: {clock: lockstep}\ndevices:\n" +
                                     vishard3("a", "{xyz: [0, 0, 0]}", "[0, 0, 0]") +
                                     vishard3("b", "{xyz: [1, 0, 0]}", "[0, 0, 0]") + groups);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("groups:\n  - name: g\n    devices: [a, c]\n").find("groups[0].devices[1]: no device 'c'"),
            std::string::npos)
      << error_of("groups:\n  - name: g\n    devices: [a, c]\n");
  EXPECT_NE(error_of("groups:\n  - {name: g, devices: [a]}\n  - {name: h, devices: [a, b]}\n")
                .find("device 'a' is in a group already"),
            std::string::npos);
  EXPECT_NE(error_of("groups:\n  - {name: g, devices: [a, b], min_distance_m: -1}\n").find("min_distance_m"),
            std::string::npos);
  EXPECT_NE(error_of("groups:\n  - {name: g, devices: [a, b], repulsion: {distance_m: 0.1, stifness_n_per_m: 5}}\n")
                .find("groups[0].repulsion"),
            std::string::npos);
  const std::string inside = error_of(
      "groups:\n  - name: g\n    devices: [a, b]\n    min_distance_m: 0.05\n    repulsion: {distance_m: 0.04}\n");
  EXPECT_NE(inside.find("session.yaml:43: groups[0].repulsion.distance_m"), std::string::npos) << inside;
  EXPECT_NE(inside.find("farther out than the hard minimum"), std::string::npos) << inside;
}

TEST(DeviceGroups, EveryRepulsionSettingOfTheFileIsTaken) {
  Session s = test::build_test_session(
      facing_pair("8", 0.03,
                  "    repulsion: {distance_m: 0.2, stiffness_n_per_m: 800, damping_n_s_per_m: 12, max_force_n: 9, "
                  "filter_hz: 5}\n"));
  const RepulsionSettings& r = s.impl().config.groups.at(0).repulsion;
  EXPECT_EQ(r.distance_m, 0.2);
  EXPECT_EQ(r.stiffness_n_per_m, 800.0);
  EXPECT_EQ(r.damping_n_s_per_m, 12.0);
  EXPECT_EQ(r.max_force_n, 9.0);
  EXPECT_EQ(r.filter_hz, 5.0);  // was read and then dropped
}

}  // namespace
}  // namespace hapticd::server
