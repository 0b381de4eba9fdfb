// Two ViSHaRD10 side by side as a dual-arm station (redundancy_ik, resolved acceleration, admittance display), their
// SCARA elbows bulging towards each other, the operators pushing the handles towards each other: with the
// clearance criterion in the inverse kinematics' null space the elbows swing apart and the clearance stays above
// its margin's reach, while the handles move as without it.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "assembly/session_impl.hpp"
#include "hapticd/server/session.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

std::string arm(const std::string& name, const std::string& base, const std::string& initial, const std::string& push,
                const std::string& clearance) {
  return test::sim_wrench_step_device_yaml(name, "vishard10", initial, push, "[0, 0, 0]") + "    base_pose: " + base +
         R"(
    virtual_model:
      plugin: admittance
      parameters: {mass_kg: [4, 4, 4], damping_n_s_per_m: [20, 20, 20], inertia_kg_m2: [0.1, 0.1, 0.1],
                   rotational_damping_n_m_s: [0.5, 0.5, 0.5]}
    inverse_kinematics:
      plugin: redundancy_ik
      parameters: {task: full, inverse: pseudoinverse, null_space_damping: 20, )" +
         clearance + R"(}
    controller:
      plugin: resolved_acceleration
      parameters: {task: full, bandwidth_rad_s: 20, rotational_bandwidth_rad_s: 40}
)";
}

// The station; `min_distance_m` the group's hard minimum (0: none).
std::string station(const std::string& clearance, double min_distance_m) {
  return std::string("server: {clock: lockstep, seed: 9}\ndevices:\n") +
         arm("left", "{xyz: [0, 0.25, 0]}", "[-0.8, 1.6, -1.6, 1.6, -0.8, 1.0, -2.0, 1.0, 1.3, 0.0]", "[0, -2, 0]",
             clearance) +
         arm("right", "{xyz: [0, -0.25, 0]}", "[0.8, -1.6, 1.6, -1.6, 0.8, 1.0, -2.0, 1.0, 1.3, 0.0]", "[0, 2, 0]",
             clearance) +
         "groups:\n  - name: station\n    devices: [left, right]\n    min_distance_m: " +
         std::to_string(min_distance_m) + "\n";
}

const CollisionGuard& guard_of(Session& s) { return *s.impl().stages.at(0)->guards().at(0); }

TEST(DualArmClearance, TheElbowsMoveApartInTheNullSpaceWithoutMovingTheHandles) {
  // 1.5 s; the pushes (2 N each, from 0.2 s) bring the handles 0.2 m closer. Without the criterion the SCARA links
  // run into each other (no hard minimum there, so the run goes on); with it the hard minimum of 0.05 m never
  // trips, and each handle stays within 3 mm of where it is without the criterion.
  Session with =
      test::build_test_session(station("clearance: 1.0, clearance_margin_m: 0.15, null_space_gain: 1", 0.05));
  Session without = test::build_test_session(station("clearance: 0.0", 0.0));
  double handle_difference = 0.0;
  for (int k = 0; k < 1500; ++k) {
    with.step(2);
    without.step(2);
    for (const char* name : {"left", "right"}) {
      ASSERT_TRUE(with.device(name).fault.empty()) << name << ": " << with.device(name).fault;
      handle_difference =
          std::max(handle_difference,
                   (with.device(name).handle_pose.position - without.device(name).handle_pose.position).norm());
    }
  }
  EXPECT_LT(guard_of(without).smallest_distance(), 0.0) << "the arms must be on a collision course";
  EXPECT_GT(guard_of(with).smallest_distance(), 0.07);
  EXPECT_EQ(guard_of(with).trips(), 0u);
  EXPECT_LT(handle_difference, 0.003);
  // The handles did move as pushed.
  EXPECT_LT(with.device("left").handle_pose.position.y() - with.device("right").handle_pose.position.y(), 0.32);
}

}  // namespace
}  // namespace hapticd::server
