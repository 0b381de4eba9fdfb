// Tests of the example plugins outside the server, as a plugin author writes them: each plugin driven through its
// interface with hand-made inputs, the SDK's test helpers (hapticd::testing: PassThroughRenderPort for the
// virtual models, AllocationGuard for "no allocation in the real-time methods").
#include <gtest/gtest.h>

#include <hapticd/chain_state.hpp>
#include <hapticd/engine_input.hpp>
#include <hapticd/testing/allocation_guard.hpp>
#include <hapticd/testing/parameters.hpp>
#include <hapticd/testing/pass_through_render_port.hpp>
#include <limits>
#include <vector>

#include "linear_axis_device.hpp"
#include "point_mass_model.hpp"
#include "spring_link_group_model.hpp"
#include "wall_model.hpp"

namespace {

constexpr std::int64_t kPeriodNs = 500'000;  // 2 kHz
hapticd::CycleTime cycle_at(std::uint64_t k) { return {static_cast<std::int64_t>(k) * kPeriodNs, kPeriodNs, k}; }

using hapticd::testing::parameters_of;  // the schema's defaults and the values given, checked as a session file's

// What a virtual model reads each cycle; the test moves the handle and pushes it.
struct ModelRig {
  hapticd::DeviceState device;
  hapticd::ChainState chain;
  hapticd::EngineInput engine;
  hapticd::testing::PassThroughRenderPort render;
  hapticd::VirtualModelInput input() { return {device, chain, engine, render}; }
};

TEST(ExampleWall, PushesTheHandleOutOfTheWallThroughTheRenderLimits) {
  example::WallModel wall;
  wall.configure(parameters_of(example::WallModel::parameter_schema(), {{"height_m", 0.1}}), {});
  ModelRig rig;
  hapticd::TaskTarget target;
  ASSERT_TRUE(wall.activate(rig.input()).ok());
  rig.chain.handle_pose.position = {0.0, 0.0, 0.2};  // above: no force
  ASSERT_TRUE(wall.update(cycle_at(1), rig.input(), target).ok());
  EXPECT_EQ(target.wrench.force, Eigen::Vector3d::Zero());
  rig.chain.handle_pose.position = {0.0, 0.0, 0.09};  // 1 cm in: 2000 N/m -> 20 N up
  hapticd::testing::AllocationGuard guard;
  ASSERT_TRUE(wall.update(cycle_at(2), rig.input(), target).ok());
  if (hapticd::testing::AllocationGuard::available()) EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_NEAR(target.wrench.force.z(), 20.0, 1e-9);
  EXPECT_TRUE(target.has_wrench);
  EXPECT_EQ(rig.render.limit_calls, 2);  // every cycle's wrench went through the safety layer's limits
}

TEST(ExamplePointMass, AcceleratesAsItsMassUnderTheOperatorsForceAndTakesTheSafetyForce) {
  example::PointMassModel mass;
  mass.configure(
      parameters_of(example::PointMassModel::parameter_schema(), {{"mass_kg", 2.0}, {"damping_n_s_per_m", 0.0}}), {});
  ModelRig rig;
  rig.chain.handle_pose.position = {0.1, 0.0, 0.0};
  hapticd::TaskTarget target;
  ASSERT_TRUE(mass.activate(rig.input()).ok());
  rig.chain.operator_wrench.force = {1.0, 0.0, 0.0};
  hapticd::testing::AllocationGuard guard;
  for (std::uint64_t k = 1; k <= 2000; ++k) ASSERT_TRUE(mass.update(cycle_at(k), rig.input(), target).ok());  // 1 s
  if (hapticd::testing::AllocationGuard::available()) EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_TRUE(target.has_motion);
  EXPECT_NEAR(target.twist.linear.x(), 0.5, 1e-9);          // v = F t / m
  EXPECT_NEAR(target.pose.position.x(), 0.1 + 0.25, 1e-3);  // x0 + F t^2 / (2 m)
  EXPECT_NEAR(target.acceleration.linear.x(), 0.5, 1e-12);
  EXPECT_EQ(rig.render.safety_force_takes, 2000);  // it renders the supervisor's force: the server need not
}

TEST(ExampleLinearAxis, MovesUnderTheWrittenForceAndRefusesANonFiniteOne) {
  example::LinearAxisDevice axis;
  axis.configure(
      parameters_of(example::LinearAxisDevice::parameter_schema(), {{"mass_kg", 0.5}, {"friction_n_s_per_m", 0.0}}),
      {});
  ASSERT_EQ(axis.description().dof(), 1);
  EXPECT_TRUE(axis.description().simulated);
  ASSERT_TRUE(axis.enable().ok());
  hapticd::DeviceState state;
  hapticd::JointCommand command;
  command.torque_nm.setConstant(1, 0.05);
  hapticd::testing::AllocationGuard guard;
  for (std::uint64_t k = 0; k <= 400; ++k) {  // 0.2 s
    ASSERT_TRUE(axis.read(cycle_at(k), state).ok());
    ASSERT_TRUE(axis.write(cycle_at(k), command).ok());
  }
  if (hapticd::testing::AllocationGuard::available()) EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_NEAR(state.joints.velocity[0], 0.05 / 0.5 * 0.2, 1e-3);  // a = F / m for 0.2 s
  command.torque_nm[0] = std::numeric_limits<double>::quiet_NaN();
  const hapticd::Outcome refused = axis.write(cycle_at(401), command);
  EXPECT_FALSE(refused.ok());
  EXPECT_STREQ(refused.reason, "a non-finite force was commanded");
  axis.disable();
}

TEST(ExampleSpringLink, PullsTheTwoHandsTogetherAndIsTunable) {
  example::SpringLinkGroupModel link;
  hapticd::GroupModelContext context;
  context.group_name = "pair";
  context.devices = {"left", "right"};
  const hapticd::ParameterSchema schema = example::SpringLinkGroupModel::parameter_schema();
  link.configure(parameters_of(schema, {{"rest_length_m", 0.2}, {"stiffness_n_per_m", 100.0}}), context);
  std::vector<hapticd::GroupHand> hands(2);
  hands[0].pose.position = {0.0, 0.0, 0.0};
  hands[1].pose.position = {0.3, 0.0, 0.0};
  std::vector<Eigen::Vector3d> forces(2, Eigen::Vector3d::Zero());
  ASSERT_TRUE(link.activate(hands).ok());
  ASSERT_TRUE(link.update(cycle_at(1), hands, forces).ok());
  EXPECT_NEAR(forces[0].x(), 10.0, 1e-9);  // 100 N/m * 0.1 m, towards the other hand
  EXPECT_NEAR(forces[1].x(), -10.0, 1e-9);
  link.tune(parameters_of(schema, {{"rest_length_m", 0.2}, {"stiffness_n_per_m", 300.0}}));  // a run-time request
  ASSERT_TRUE(link.update(cycle_at(2), hands, forces).ok());
  EXPECT_NEAR(forces[0].x(), 30.0, 1e-9);
  // A group of one is refused at configure time, with the key-less ParameterError naming the group.
  context.devices = {"left"};
  EXPECT_THROW(link.configure(parameters_of(schema), context), hapticd::ParameterError);
}

}  // namespace
