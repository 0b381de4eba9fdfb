// Faults latch (lockstep): an E-stop after a recovery request cancels that request, a stop while the device is
// already safe is a fault of its own, recovery happens only on a request made after the last stop, and every
// fault and recovery is in the device's log. A loop that wakes far too late (a stalled process) is a fault.
#include <gtest/gtest.h>

#include "session/device_session.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;

std::string vishard3_session(const std::string& safety = "") {
  return test::sim_vishard3_admittance_session("v3", 5, safety);
}

std::vector<SafetyEvent> drain(DeviceSession& d) {
  std::vector<SafetyEvent> events;
  SafetyEvent e;
  while (d.status().take_safety_event(e)) events.push_back(e);
  return events;
}

TEST(FaultLatch, AStopAfterARecoveryRequestCancelsIt) {
  // The attack: client A stops, 0.15 s later A asks for recovery, 0.15 s later client B stops. The device must
  // stay in its safe mode (it recovered 0.48 s later and ran on); both stops are faults.
  auto s = test::build_test_session(vishard3_session());
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 6000; ++k) {
    if (k == 2000) d.requests().emergency_stop();  // A
    if (k == 2300) {
      EXPECT_TRUE(d.requests().recover().accepted);  // A
    }
    if (k == 2600) d.requests().emergency_stop();  // B
    d.cycle(cycle_at(k), 1.0);
    d.service();
  }
  EXPECT_EQ(d.status().fault(), DeviceFault::emergency_stop);
  EXPECT_EQ(d.status().recoveries(), 0u);
  EXPECT_EQ(d.status().faults_raised(), 2u);
  const auto events = drain(d);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, SafetyEvent::Kind::fault);
  EXPECT_EQ(events[0].cycle, 2000u);
  EXPECT_EQ(events[1].kind, SafetyEvent::Kind::fault);
  EXPECT_EQ(events[1].fault, DeviceFault::emergency_stop);
  EXPECT_EQ(events[1].cycle, 2600u);
  // A fault report for each stop.
  FaultReport report;
  ASSERT_TRUE(d.status().take_fault_report(report));
  EXPECT_EQ(report.serial, 2u);
  EXPECT_EQ(report.cycle, 2600u);
  d.deactivate();
}

TEST(FaultLatch, OnlyARequestAfterTheLastStopRecovers) {
  auto s = test::build_test_session(vishard3_session());
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  std::uint64_t recovered_at = 0;
  for (std::uint64_t k = 0; k < 8000; ++k) {
    if (k == 2000) d.requests().emergency_stop();
    if (k == 2100) {
      EXPECT_TRUE(d.requests().recover().accepted);
    }
    if (k == 2200) d.requests().emergency_stop();
    if (k == 2300) d.requests().emergency_stop();  // a third stop, still before the new request
    if (k == 5000) {
      EXPECT_TRUE(d.requests().recover().accepted);
    }
    d.cycle(cycle_at(k), 1.0);
    d.service();
    if (k >= 2000 && k < 5000) {
      ASSERT_NE(d.status().fault(), DeviceFault::none) << "recovered at cycle " << k << " on a voided request";
    }
    if (recovered_at == 0 && k >= 5000 && d.status().fault() == DeviceFault::none) recovered_at = k;
  }
  EXPECT_EQ(recovered_at, 5000u);  // the safe mode had long settled: at once
  EXPECT_EQ(d.status().faults_raised(), 3u);
  EXPECT_EQ(d.status().recoveries(), 1u);
  const auto events = drain(d);
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(events[3].kind, SafetyEvent::Kind::recovery);
  EXPECT_EQ(events[3].fault, DeviceFault::emergency_stop);
  EXPECT_EQ(events[3].cycle, 5000u);
  d.deactivate();
}

TEST(FaultLatch, AStallOfTheLoopIsAFault) {
  // The process was stopped for 2 s (SIGSTOP): the loop wakes 2 s late for a cycle. Before, that was one
  // overrun and no fault. A few periods late (below max_stall_s) is not a stall.
  auto s = test::build_test_session(vishard3_session("max_stall_s: 0.005"));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 3000; ++k) {
    const std::int64_t late_ns = k == 1000 ? 4'000'000 : k == 2000 ? 2'000'000'000 : 0;
    d.cycle(cycle_at(k), 1.0, 0, late_ns);
    d.service();
    if (k == 1000) {
      EXPECT_EQ(d.status().fault(), DeviceFault::none) << "4 ms late is within max_stall_s";
    }
  }
  EXPECT_EQ(d.status().fault(), DeviceFault::loop_stall);
  EXPECT_EQ(d.status().fault_cycle(), 2000u);
  EXPECT_EQ(fault_code(DeviceFault::loop_stall), "loop_stall");
  d.deactivate();
}

}  // namespace
}  // namespace hapticd::server
