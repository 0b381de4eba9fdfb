// A device session checks every plugin output before it reaches a motor; a fault puts that device - and only
// that device - in its safe state; the chain's cycle never allocates.
#include "session/device_session.hpp"

#include <gtest/gtest.h>

#include "app/served_session.hpp"
#include "cycle/loop_cycle.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "recorder/recorder.hpp"
#include "support/handle_mass_urdf.hpp"
#include "support/temp_file.hpp"
#include "support/test_paths.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;

server::Session session_with(const std::string& devices) {
  return test::build_test_session("server: {clock: lockstep}\ndevices:\n" + devices);
}

TEST(DeviceSession, NonFiniteControllerOutputPutsTheDeviceInItsSafeModeDampingThenZeroTorque) {
  // Safe mode: the last torque fades out over 20 ms while joint damping acts for safe_damping_s (0.5 s = 1000
  // cycles at 2 kHz), then exactly zero torque.
  auto s = session_with(test::mass_spring_device_yaml("axis", "", ", fault_at_cycle: 100"));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 100; ++k) d.cycle(cycle_at(k), 1.0);
  EXPECT_EQ(d.status().fault(), DeviceFault::none);
  EXPECT_NE(d.command().torque_nm[0], 0.0);
  int damping_cycles = 0;
  for (std::uint64_t k = 100; k < 1300; ++k) {
    d.cycle(cycle_at(k), 1.0);
    const double tau = d.command().torque_nm[0];
    const double v = d.state().joints.velocity[0];
    if (k < 1100) {
      // After the 20 ms fade of the last torque (40 cycles): damping, against the motion, proportional to it.
      if (k >= 140) {
        ASSERT_NEAR(tau, -d.safety().settings().safe_damping_gain * v, 1e-12) << "cycle " << k;
      }
      ASSERT_FALSE(d.status().at_rest()) << "cycle " << k;
      if (tau != 0.0) ++damping_cycles;
    } else {
      ASSERT_EQ(tau, 0.0) << "cycle " << k;
      ASSERT_TRUE(d.status().at_rest());
      // The effort read at cycle k is the force held since cycle k-1.
      if (k > 1100) {
        ASSERT_EQ(d.state().joints.effort[0], 0.0) << "the device applies force after the safe mode, cycle " << k;
      }
    }
  }
  EXPECT_GT(damping_cycles, 900);  // the axis was moving: the damping acted
  EXPECT_EQ(d.status().fault(), DeviceFault::non_finite_output);
  EXPECT_EQ(d.status().fault_cycle(), 100u);
  d.deactivate();
}

TEST(DeviceSession, ReadFailureIsAFault) {
  auto s = session_with(test::mass_spring_device_yaml("axis", ", fail_read_at_cycle: 10"));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 20; ++k) d.cycle(cycle_at(k), 1.0);
  EXPECT_EQ(d.status().fault(), DeviceFault::device_read);
  EXPECT_EQ(d.status().fault_cycle(), 10u);
  EXPECT_EQ(d.command().torque_nm[0], 0.0);
}

TEST(DeviceSession, TorqueIsClampedToThePeak) {
  // Force limit 5 N and a stiff PD: the command saturates, and is counted.
  auto s = session_with(test::mass_spring_device_yaml("axis", ", force_limit_n: 5", ", kp: 5000"));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 400; ++k) {
    d.cycle(cycle_at(k), 1.0);
    ASSERT_LE(std::abs(d.command().torque_nm[0]), 5.0);
  }
  EXPECT_GT(d.status().saturated_cycles(), 0u);
  EXPECT_EQ(d.status().fault(), DeviceFault::none);
}

TEST(DeviceSession, FaultOfOneDeviceLeavesTheOtherUndisturbed) {
  // Device "b" runs alone, then beside a device that faults: its trajectory must be bit-identical.
  auto alone = session_with(test::mass_spring_device_yaml("b"));
  auto together =
      session_with(test::mass_spring_device_yaml("a", "", ", fault_at_cycle: 50") + test::mass_spring_device_yaml("b"));
  alone.impl().devices[0]->activate();
  for (auto& d : together.impl().devices) d->activate();
  for (std::uint64_t k = 0; k < 2000; ++k) {
    alone.impl().devices[0]->cycle(cycle_at(k), 1.0);
    for (auto& d : together.impl().devices) d->cycle(cycle_at(k), 1.0);
    ASSERT_EQ(alone.impl().devices[0]->state().joints.position[0],
              together.impl().devices[1]->state().joints.position[0])
        << k;
  }
  EXPECT_EQ(together.impl().devices[0]->status().fault(), DeviceFault::non_finite_output);
  EXPECT_EQ(together.impl().devices[1]->status().fault(), DeviceFault::none);
}

TEST(DeviceSession, CycleOfTheWholeChainDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting is off under sanitizers";
  auto s = session_with(test::mass_spring_device_yaml("axis", ", position_noise_m: 1.0e-5"));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  testing::AllocationGuard guard;
  for (std::uint64_t k = 0; k < 5000; ++k) d.cycle(cycle_at(k), k < 4000 ? 1.0 : 0.5);
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_EQ(d.status().fault(), DeviceFault::none);
}

TEST(DeviceSession, SnapshotsForTheDdsInterfaceAndTheLiveViewDoNotAllocate) {
  // Both hand-offs at their own intervals; each reader takes only its own.
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting is off under sanitizers";
  auto s = session_with(test::mass_spring_device_yaml("axis", ", position_noise_m: 1.0e-5"));
  DeviceSession& d = *s.impl().devices[0];
  d.set_snapshot_interval(2);
  d.set_view_interval(3);
  d.activate();
  DeviceSnapshot view, dds;
  testing::AllocationGuard guard;
  for (std::uint64_t k = 0; k < 5000; ++k) d.cycle(cycle_at(k), 1.0);
  EXPECT_EQ(guard.allocations(), 0u);
  ASSERT_TRUE(d.status().take_view_snapshot(view));
  ASSERT_TRUE(d.status().take_snapshot(dds));
  EXPECT_EQ(view.cycle, 4998u);                       // the newest multiple of 3 below 5000
  EXPECT_EQ(dds.cycle, 4998u);                        // ... and of 2
  EXPECT_FALSE(d.status().take_view_snapshot(view));  // taken once
  d.cycle(cycle_at(5000), 1.0);
  EXPECT_FALSE(d.status().take_view_snapshot(view));  // 5000 is not the view's
  ASSERT_TRUE(d.status().take_snapshot(dds));
  EXPECT_EQ(dds.cycle, 5000u);
  d.cycle(cycle_at(5001), 1.0);
  ASSERT_TRUE(d.status().take_view_snapshot(view));
  EXPECT_EQ(view.cycle, 5001u);
}

TEST(DeviceSession, ARecordedCycleDoesNotAllocate) {
  // The loop's side of the recording: the cycle snapshot, the record and the ring (real-time mode: a full ring
  // drops, so the writer thread's pace does not matter here).
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting is off under sanitizers";
  auto s = session_with(test::mass_spring_device_yaml("axis", ", position_noise_m: 1.0e-5"));
  const auto file = test::write_temp_file("alloc.h5", "");
  Recorder recorder(file, recording_header(s.impl().config, s.impl().device_pointers()), /*wait_when_full=*/false);
  LoopCycle loop(s.impl().device_pointers(), {}, &recorder);
  s.impl().devices[0]->activate();
  testing::AllocationGuard guard;
  for (std::uint64_t k = 0; k < 5000; ++k) loop.run_cycle(cycle_at(k), 1.0, 0, 0);
  EXPECT_EQ(guard.allocations(), 0u);
  recorder.close();
  EXPECT_FALSE(recorder.failed()) << recorder.error();
  EXPECT_EQ(recorder.written() + recorder.dropped(), 5000u);
}

// A simulated ViSHaRD3 pushed by a scripted force, held by the test PD controller.
const std::string kSimVishard3 =
    test::sim_vishard3_device_yaml("v3", "constant", "[10.0, 0.0, 0.0]") + R"(    controller:
      plugin: test_pd
      parameters: {kp: 300, kd: 3, hold_at_activation: true}
)";

TEST(DeviceSession, SharesTheModelTermsOfEveryCycleWithTheChain) {
  auto s = session_with(kSimVishard3);
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 400; ++k) d.cycle(cycle_at(k), 1.0);
  ASSERT_EQ(d.status().fault(), DeviceFault::none);
  const ChainState& c = d.chain_state();
  ASSERT_NE(c.model, nullptr);
  ASSERT_NE(c.data, nullptr);
  // The handle pose is the model's FK at the measured positions.
  model::ModelData check(*c.model);
  model::forward_kinematics(*c.model, check, d.state().joints.position);
  EXPECT_LE((model::frame_pose(*c.model, check, c.handle_frame).translation() - c.handle_pose.position).norm(), 1e-12);
  // The operator wrench in the world is the scripted 10 N along x (sensor noise and resolution aside).
  EXPECT_NEAR(c.operator_wrench.force.x(), 10.0, 0.3);
  EXPECT_NEAR(c.operator_wrench.force.y(), 0.0, 0.3);
  EXPECT_TRUE(c.has_operator_wrench);
  EXPECT_EQ(d.state().joints.velocity.size(), 3);
}

TEST(DeviceSession, OperatorWrenchLeavesOutTheWeightOfWhatTheSensorCarries) {
  // A 0.5 kg handle beyond the sensor: the sensor reads its weight besides the 10 N push; the estimate of the
  // operator's wrench is the push alone (the model's carried mass times gravity subtracted).
  std::string yaml = kSimVishard3;
  const std::string model = hapticd::test::source_dir() + "/config/urdf/vishard3.urdf";
  yaml.replace(yaml.find(model), model.size(), test::vishard3_urdf_with_handle_mass(0.5));
  auto s = session_with(yaml);
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 400; ++k) d.cycle(cycle_at(k), 1.0);
  ASSERT_EQ(d.status().fault(), DeviceFault::none);
  const ChainState& c = d.chain_state();
  // The sensor reads the weight (its frame is the handle's).
  EXPECT_NEAR((c.handle_pose.orientation * d.state().sensor_wrench.force).z(), -0.5 * 9.81, 0.3);
  EXPECT_NEAR(c.operator_wrench.force.x(), 10.0, 0.3);
  EXPECT_NEAR(c.operator_wrench.force.z(), 0.0, 0.3);
}

TEST(DeviceSession, CycleWithModelTermsDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting is off under sanitizers";
  auto s = session_with(kSimVishard3);
  EXPECT_EQ(test::allocations_over_cycles(*s.impl().devices[0], 2000), 0u);
  EXPECT_EQ(s.impl().devices[0]->status().fault(), DeviceFault::none);
}

}  // namespace
}  // namespace hapticd::server
