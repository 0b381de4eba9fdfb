// Every model algorithm meant for the loop runs without touching the heap once ModelData exists.
#include <gtest/gtest.h>

#include <numbers>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/task_space.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "support/device_models.hpp"

namespace hapticd {
namespace {

class ModelAllocation : public ::testing::TestWithParam<const char*> {};

TEST_P(ModelAllocation, LoopAlgorithmsDoNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting is off under sanitizers";
  const model::RobotModel robot = test::load_device_model(GetParam());
  const int handle = robot.require_frame("handle");
  const int n = robot.dof();
  model::ModelData data(robot);
  std::mt19937_64 rng(1);
  const JointVector q = test::random_joint_vector(rng, n, std::numbers::pi);
  const JointVector qd = test::random_joint_vector(rng, n, 2.0);
  const JointVector qdd = test::random_joint_vector(rng, n, 2.0);
  JointVector tau(n), qdd_out(n);
  JointMatrix c(n, n);
  model::TaskJacobian j, analytic, translation;
  model::TaskMatrix lambda;
  double sink = 0.0;

  const std::size_t allocations = testing::count_allocations([&] {
    model::compute_cycle_terms(robot, data, q, qd, handle);
    model::forward_kinematics(robot, data, q);
    sink += model::frame_pose(robot, data, handle).translation().x();
    model::frame_jacobian(robot, data, handle, j);
    model::forward_velocity(robot, data, q, qd);
    sink += model::frame_jacobian_dot_times_qd(robot, data, handle)[0];
    sink += model::frame_velocity(robot, data, handle)[0];
    sink += model::analytic_jacobian(j, data.frame_pose.linear(), analytic) ? 1.0 : 0.0;
    model::joint_space_inertia(robot, data);
    model::gravity_torques(robot, data);
    model::coriolis_torques(robot, data);
    model::coriolis_matrix(robot, data, c);
    model::inverse_dynamics(robot, data, qdd, tau);
    model::forward_dynamics(robot, data, tau, qdd_out);
    model::select_rows(j, model::TaskRows::translation, translation);
    sink += model::operational_space_inertia(data, translation, lambda) ? 1.0 : 0.0;
    sink += model::manipulability(translation);
    sink += model::condition_number(translation);
  });
  EXPECT_EQ(allocations, 0u);
  EXPECT_TRUE(std::isfinite(sink));
}

INSTANTIATE_TEST_SUITE_P(Devices, ModelAllocation, ::testing::ValuesIn(test::kDeviceModels));

}  // namespace
}  // namespace hapticd
