// The trajectory model on the simulated ViSHaRD3 in admittance display: its target is the profile's path from
// the handle's start with the path's analytic velocity and acceleration, the inner loop tracks it; update() does
// not allocate; a bad path names its parameter.
#include <gtest/gtest.h>

#include "support/test_session.hpp"

namespace hapticd {
namespace {

std::string trajectory_session(const std::string& path) {
  return test::sim_vishard3_session_head("v3", 3) + R"(        attachment: none
    virtual_model:
      plugin: trajectory
      parameters: {)" +
         path + R"(}
    controller:
      plugin: resolved_acceleration
      parameters: {task: translation, bandwidth_rad_s: 100, acceleration_feedforward: true}
)";
}

TEST(TrajectoryModel, PlaysTheShuttleWithItsAnalyticAccelerationAndTheHandleFollows) {
  // 10 cm along x at 2 m/s^2 up to 0.2 m/s, from 0.2 s: accelerating until 0.3 s (1 cm), cruising 8 cm until
  // 0.7 s, decelerating, there at 0.8 s.
  server::Session s = test::build_test_session(trajectory_session(
      "path: shuttle, path_m: [0.1, 0, 0], path_start_s: 0.2, path_acceleration_m_s2: 2, path_speed_m_s: 0.2"));
  s.step(1);
  const Eigen::Vector3d start = s.device("v3").task.pose.position;
  s.step(499);  // t = 0.25 s: accelerating for 0.05 s
  server::DeviceView v = s.device("v3");
  EXPECT_NEAR(v.task.acceleration.linear.x(), 2.0, 1e-9);
  EXPECT_NEAR(v.task.twist.linear.x(), 0.1, 2e-3);
  EXPECT_NEAR(v.task.pose.position.x() - start.x(), 0.5 * 2.0 * 0.05 * 0.05, 1e-4);
  s.step(400);  // t = 0.45 s: cruising
  v = s.device("v3");
  EXPECT_NEAR(v.task.acceleration.linear.x(), 0.0, 1e-9);
  EXPECT_NEAR(v.task.twist.linear.x(), 0.2, 1e-9);
  s.step(600);  // t = 0.75 s: decelerating
  v = s.device("v3");
  EXPECT_NEAR(v.task.acceleration.linear.x(), -2.0, 1e-9);
  EXPECT_NEAR(v.task.pose.position.y(), start.y(), 1e-12) << "y and z stay";
  // The inner loop follows within a millimetre.
  ASSERT_TRUE(v.fault.empty()) << v.fault;
  EXPECT_LT((v.handle_pose.position - v.task.pose.position).norm(), 1e-3);
}

TEST(TrajectoryModel, UpdateDoesNotAllocate) {
  server::Session s = test::build_test_session(trajectory_session("path: sine, path_m: [0, 0.02, 0]"));
  EXPECT_EQ(test::allocations_over_cycles(*s.impl().devices[0], 2000), 0u);
}

TEST(TrajectoryModel, ABadPathNamesItsParameter) {
  try {
    (void)test::build_test_session(trajectory_session("path: zigzag"));
    FAIL() << "an unknown path was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("path"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hapticd
