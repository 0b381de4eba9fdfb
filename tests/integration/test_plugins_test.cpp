// The test plugins: each update() is allocation-free (the harness every plugin test uses), and each does what
// it claims, so the foundation's end-to-end tests stand on something checked.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hapticd/chain_state.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "hapticd/testing/pass_through_render_port.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;

TEST(TestPlugins, EveryUpdateIsAllocationFree) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting is off under sanitizers";
  auto s = test::build_test_session("server: {clock: lockstep}\ndevices:\n" +
                                    test::mass_spring_device_yaml("a", ", position_noise_m: 1.0e-5"));
  const SchemeChain& c = s.impl().devices[0]->chain().schemes[0];
  const DeviceChain& dc = s.impl().devices[0]->chain();
  DeviceState state;
  state.joints.resize(1);
  TaskTarget task;
  JointTarget joints;
  joints.resize(1);
  JointCommand command;
  command.torque_nm.setZero(1);
  ChainState chain;  // the test device has no robot model
  const EngineInput engine;
  testing::PassThroughRenderPort render;
  ASSERT_TRUE(dc.device->enable().ok());
  ASSERT_TRUE((*c.virtual_model)->activate(VirtualModelInput{state, chain, engine, render}).ok());
  ASSERT_TRUE((*c.inverse_kinematics)->activate(InverseKinematicsInput{state, task, chain}).ok());
  ASSERT_TRUE(c.controller->activate(ControllerInput{state, task, joints, chain, nullptr}, command).ok());

  std::size_t device = 0, model = 0, ik = 0, controller = 0;
  for (std::uint64_t k = 0; k < 2000; ++k) {
    const CycleTime t = cycle_at(k);
    device += testing::count_allocations([&] { (void)dc.device->read(t, state); });
    model += testing::count_allocations([&] {
      (void)(*c.virtual_model)->update(t, VirtualModelInput{state, chain, engine, render}, task);
    });
    ik += testing::count_allocations([&] {
      (void)(*c.inverse_kinematics)->update(t, InverseKinematicsInput{state, task, chain}, joints);
    });
    controller += testing::count_allocations([&] {
      (void)c.controller->update(t, ControllerInput{state, task, joints, chain, nullptr}, command);
    });
    device += testing::count_allocations([&] { (void)dc.device->write(t, command); });
  }
  EXPECT_EQ(device, 0u);
  EXPECT_EQ(model, 0u);
  EXPECT_EQ(ik, 0u);
  EXPECT_EQ(controller, 0u);
}

TEST(TestPlugins, MassSpringOscillatesAtItsNaturalFrequency) {
  // m = 1 kg, k = 100 N/m, no damping, released from 0.1 m: period 2 pi / 10 s; count zero crossings.
  auto s = test::build_test_session(
      "server: {clock: lockstep}\ndevices:\n  - name: a\n    device:\n      plugin: test_mass_spring\n"
      "      parameters: {mass_kg: 1, stiffness_n_per_m: 100, damping_n_s_per_m: 0, initial_position_m: 0.1, substeps: "
      "20}\n"
      "    controller: {plugin: test_pd, parameters: {kp: 0, kd: 0}}\n");
  Device& device = *s.impl().devices[0]->chain().device;
  ASSERT_TRUE(device.enable().ok());
  DeviceState state;
  state.joints.resize(1);
  double previous = 0.1;
  double amplitude = 0.0;
  std::vector<double> crossings;
  for (std::uint64_t k = 1; k <= 20000; ++k) {  // 10 s
    ASSERT_TRUE(device.read(cycle_at(k), state).ok());
    const double x = state.joints.position[0];
    amplitude = std::max(amplitude, std::abs(x));
    if ((previous > 0) != (x > 0)) crossings.push_back(cycle_at(k).time_s());
    previous = x;
  }
  ASSERT_GE(crossings.size(), 20u);
  const double half_period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  EXPECT_NEAR(2.0 * half_period, 2.0 * std::numbers::pi / 10.0, 2e-3);
  EXPECT_LT(amplitude, 0.1 * 1.001);  // no energy gained over 16 periods
  EXPECT_GT(amplitude, 0.1 * 0.999);
}

TEST(TestPlugins, PdChainTracksTheSineSetpoint) {
  auto s = test::build_test_session("server: {clock: lockstep}\ndevices:\n" + test::mass_spring_device_yaml("a"));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  double worst_error = 0.0;
  for (std::uint64_t k = 0; k < 4000; ++k) {
    d.cycle(cycle_at(k), 1.0);
    if (k > 2000) {
      const double target = 0.05 * std::sin(2 * std::numbers::pi * 2.0 * cycle_at(k).time_s());
      worst_error = std::max(worst_error, std::abs(d.state().joints.position[0] - target));
    }
  }
  // 1 kg on a 100 N/m spring under kp = 400, kd = 20 lags a 2 Hz, 5 cm sine by a few millimetres, not centimetres.
  EXPECT_LT(worst_error, 0.02);
  EXPECT_GT(worst_error, 1e-4);  // and it is a real tracking loop, not a copy of the target
}

}  // namespace
}  // namespace hapticd::server
