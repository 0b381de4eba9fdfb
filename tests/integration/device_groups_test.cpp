// Device groups (`groups`): the group stage measures the clearance between the group's devices every cycle, in the
// world frame; below the group's hard minimum both devices of the pair enter their safe mode with a fault naming
// the pair and the links, and devices outside the group run on.
#include <gtest/gtest.h>

#include <string>

#include "hapticd/model/collision.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/server/session.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "session/session_impl.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

// A simulated ViSHaRD3 at `base` in admittance display (3 kg, 40 N s/m), pushed from 0.1 s on by `force`.
std::string vishard3(const std::string& name, const std::string& base, const std::string& force) {
  return test::sim_vishard3_device_yaml(name, "step", force) + "        wrench_force_start_s: 0.1\n" +
         "    base_pose: " + base + "\n" + test::vishard3_admittance_chain_yaml();
}

// Two ViSHaRD3 facing each other 0.9 m apart along x (the right one turned half a turn), their handles pushed
// towards each other by `force_n` each; a third device on its own beside them.
std::string facing_pair(const std::string& force_n, double min_distance_m) {
  return "server: {clock: lockstep, seed: 5}\ndevices:\n" +
         vishard3("left", "{xyz: [0, 0, 0]}", "[" + force_n + ", 0, 0]") +
         vishard3("right", "{xyz: [0.9, 0, 0], rpy: [0, 0, 3.141592653589793]}", "[-" + force_n + ", 0, 0]") +
         vishard3("alone", "{xyz: [0, 2, 0]}", "[0, 0, 0]") +
         "groups:\n  - name: hands\n    devices: [left, right]\n    min_distance_m: " + std::to_string(min_distance_m) +
         "\n";
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
  EXPECT_EQ(s.impl().device("left").fault(), DeviceFault::collision);
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

TEST(DeviceGroups, TheGroupStageDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  Session s = test::build_test_session(facing_pair("8", 0.03));
  s.step(10);  // powered, the chains active
  DeviceGroup& group = *s.impl().group;
  testing::AllocationGuard guard;
  for (std::uint64_t k = 10; k < 1010; ++k) group.run_cycle(test::cycle_at(k), 1.0, 0, 0);
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_LT(guard_of(s).latest_distance(), 1.0);  // the guards ran
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
}

}  // namespace
}  // namespace hapticd::server
