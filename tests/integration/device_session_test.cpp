// A device session checks every plugin output before it reaches a motor; a fault puts that device - and only
// that device - in its safe state; the chain's cycle never allocates.
#include "session/device_session.hpp"

#include <gtest/gtest.h>

#include "hapticd/testing/allocation_guard.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

constexpr std::int64_t kPeriodNs = 500'000;

CycleTime cycle_at(std::uint64_t k) { return CycleTime{static_cast<std::int64_t>(k) * kPeriodNs, kPeriodNs, k}; }

test::TestSession session_with(const std::string& devices) {
  return test::build_test_session("server: {clock: lockstep}\ndevices:\n" + devices);
}

TEST(DeviceSession, NonFiniteControllerOutputStopsTheDeviceWithZeroTorque) {
  auto s = session_with(test::mass_spring_device_yaml("axis", "", ", fault_at_cycle: 100"));
  DeviceSession& d = *s.devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 100; ++k) d.cycle(cycle_at(k), 1.0);
  EXPECT_EQ(d.fault(), DeviceFault::none);
  EXPECT_NE(d.command().torque_nm[0], 0.0);
  for (std::uint64_t k = 100; k < 200; ++k) {
    d.cycle(cycle_at(k), 1.0);
    ASSERT_EQ(d.command().torque_nm[0], 0.0) << "cycle " << k;
    // The effort read at cycle k is the force held since cycle k-1.
    if (k > 100) {
      ASSERT_EQ(d.state().joints.effort[0], 0.0) << "the device applies force after the fault, cycle " << k;
    }
  }
  EXPECT_EQ(d.fault(), DeviceFault::non_finite_output);
  EXPECT_EQ(d.fault_cycle(), 100u);
  d.deactivate();
}

TEST(DeviceSession, ReadFailureIsAFault) {
  auto s = session_with(test::mass_spring_device_yaml("axis", ", fail_read_at_cycle: 10"));
  DeviceSession& d = *s.devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 20; ++k) d.cycle(cycle_at(k), 1.0);
  EXPECT_EQ(d.fault(), DeviceFault::device_read);
  EXPECT_EQ(d.fault_cycle(), 10u);
  EXPECT_EQ(d.command().torque_nm[0], 0.0);
}

TEST(DeviceSession, TorqueIsClampedToThePeak) {
  // Force limit 5 N and a stiff PD: the command saturates, and is counted.
  auto s = session_with(test::mass_spring_device_yaml("axis", ", force_limit_n: 5", ", kp: 5000"));
  DeviceSession& d = *s.devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 400; ++k) {
    d.cycle(cycle_at(k), 1.0);
    ASSERT_LE(std::abs(d.command().torque_nm[0]), 5.0);
  }
  EXPECT_GT(d.saturated_cycles(), 0u);
  EXPECT_EQ(d.fault(), DeviceFault::none);
}

TEST(DeviceSession, FaultOfOneDeviceLeavesTheOtherUndisturbed) {
  // Device "b" runs alone, then beside a device that faults: its trajectory must be bit-identical.
  auto alone = session_with(test::mass_spring_device_yaml("b"));
  auto together = session_with(test::mass_spring_device_yaml("a", "", ", fault_at_cycle: 50") +
                               test::mass_spring_device_yaml("b"));
  alone.devices[0]->activate();
  for (auto& d : together.devices) d->activate();
  for (std::uint64_t k = 0; k < 2000; ++k) {
    alone.devices[0]->cycle(cycle_at(k), 1.0);
    for (auto& d : together.devices) d->cycle(cycle_at(k), 1.0);
    ASSERT_EQ(alone.devices[0]->state().joints.position[0], together.devices[1]->state().joints.position[0]) << k;
  }
  EXPECT_EQ(together.devices[0]->fault(), DeviceFault::non_finite_output);
  EXPECT_EQ(together.devices[1]->fault(), DeviceFault::none);
}

TEST(DeviceSession, CycleOfTheWholeChainDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting is off under sanitizers";
  auto s = session_with(test::mass_spring_device_yaml("axis", ", position_noise_m: 1.0e-5"));
  DeviceSession& d = *s.devices[0];
  d.activate();
  testing::AllocationGuard guard;
  for (std::uint64_t k = 0; k < 5000; ++k) d.cycle(cycle_at(k), k < 4000 ? 1.0 : 0.5);
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_EQ(d.fault(), DeviceFault::none);
}

}  // namespace
}  // namespace hapticd::server
