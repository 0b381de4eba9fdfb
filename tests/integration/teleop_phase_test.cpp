// The teleoperation link's side in the device's cycle (session/teleop_phase.hpp, docs/teleoperation.md "One control
// path"): a packet delivered before a cycle is felt in that cycle; the peer's stop stops the device; the loop's
// newest packet goes out; a full inbox drops and counts, and a peer change stays in order behind it; the cycle never
// allocates, with packets flowing.
#include "session/teleop_phase.hpp"

#include <gtest/gtest.h>

#include "hapticd/testing/allocation_guard.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;

teleop::LinkSettings plain_position_force() {
  teleop::LinkSettings s;
  s.architecture = teleop::Architecture::position_force;
  s.passivity = teleop::Passivity::none;  // the remote's force displayed as it comes
  return s;
}

// The remote's packet of serial `k`, sent at cycle k, pushing back with `force`.
teleop::LinkPacket remote_packet(std::uint64_t k, const Eigen::Vector3d& force, bool stopped = false) {
  teleop::LinkPacket p;
  p.sequence = k;
  p.sent_ns = cycle_at(k).time_ns;
  p.force = force;
  p.stopped = stopped;
  return p;
}

struct MasterSide {
  server::Session session = test::build_test_session(test::sim_vishard3_admittance_session("master", 3));
  DeviceSession& device = test::device_of(session);
  TeleopPhase* phase = nullptr;
  MasterSide() {
    device.enable_teleoperation(teleop::Role::master, plain_position_force());
    device.set_snapshot_every_cycle(true);
    phase = device.requests().teleoperation();
    device.activate();
  }
};

TEST(TeleopPhase, APacketDeliveredBeforeACycleIsFeltInThatCycle) {
  MasterSide m;
  ASSERT_NE(m.phase, nullptr);
  std::uint64_t k = 0;
  for (; k < 200; ++k) {
    ASSERT_TRUE(m.phase->deliver(remote_packet(k + 1, {-3.0, 0, 0}), cycle_at(k).time_ns));
    m.device.cycle(cycle_at(k), 1.0);
  }
  EXPECT_NEAR(m.device.published_snapshot().engine_wrench.force.x(), -3.0, 1e-9);
  // A new force: in the very cycle its packet was delivered before (no hand-off through another thread's cycle).
  ASSERT_TRUE(m.phase->deliver(remote_packet(k + 1, {-7.0, 0, 0}), cycle_at(k).time_ns));
  m.device.cycle(cycle_at(k), 1.0);
  EXPECT_NEAR(m.device.published_snapshot().engine_wrench.force.x(), -7.0, 1e-9);
  EXPECT_GT(m.device.engine_weight(), 0.99);
  // The loop's newest packet goes out: this cycle's, with the handle's position.
  teleop::LinkPacket out;
  ASSERT_TRUE(m.phase->take_outgoing(out));
  EXPECT_EQ(out.sent_ns, cycle_at(k).time_ns);
  EXPECT_TRUE(out.has_echo);
  EXPECT_EQ(out.echo_sent_ns, cycle_at(k + 1).time_ns);  // the newest packet taken, echoed
  EXPECT_FALSE(m.phase->take_outgoing(out));             // once
  TeleopReport r;
  ASSERT_TRUE(m.phase->take_report(r));
  EXPECT_EQ(r.received, 201u);
  EXPECT_NEAR(r.max_force, 7.0, 1e-9);
  EXPECT_EQ(m.device.status().fault(), DeviceFault::none);
}

TEST(TeleopPhase, ThePeersStopStopsTheDeviceAtTheNextCycle) {
  MasterSide m;
  std::uint64_t k = 0;
  for (; k < 100; ++k) {
    m.phase->deliver(remote_packet(k + 1, {-1.0, 0, 0}), cycle_at(k).time_ns);
    m.device.cycle(cycle_at(k), 1.0);
  }
  m.phase->deliver(remote_packet(k + 1, {-1.0, 0, 0}, true), cycle_at(k).time_ns);
  m.device.cycle(cycle_at(k++), 1.0);  // the port decides the stop: the E-stop, as any door's, is the loop's next
  m.device.cycle(cycle_at(k++), 1.0);
  EXPECT_EQ(m.device.status().fault(), DeviceFault::emergency_stop);
  TeleopReport r;
  ASSERT_TRUE(m.phase->take_report(r));
  EXPECT_EQ(r.peer_stops, 1u);
  // Stopped: no force is handed to the device (its safe mode runs), and its packets say it stopped.
  teleop::LinkPacket out;
  ASSERT_TRUE(m.phase->take_outgoing(out));
  EXPECT_TRUE(out.stopped);
}

TEST(TeleopPhase, AFullInboxDropsAndCountsAndNothingIsLostAfter) {
  MasterSide m;
  int accepted = 0;
  for (std::uint64_t k = 1; k <= 300; ++k) accepted += m.phase->deliver(remote_packet(k, {-2.0, 0, 0}), 0) ? 1 : 0;
  EXPECT_EQ(accepted, 256);
  m.device.cycle(cycle_at(0), 1.0);
  TeleopReport r;
  ASSERT_TRUE(m.phase->take_report(r));
  EXPECT_EQ(r.dropped, 44u);
  EXPECT_EQ(r.received, 256u);
  EXPECT_TRUE(m.phase->deliver(remote_packet(301, {-2.0, 0, 0}), 0));  // room again after the cycle took them
}

TEST(TeleopPhase, APeerChangeWithTheInboxFullStaysBehindTheOldPeersPackets) {
  // A restarted peer while the loop is behind: the old peer's packets (high serials) fill the ring. The change must
  // reach the port after them, or the new peer's serials (from 1 again) read as old and the link is lost.
  MasterSide m;
  for (std::uint64_t k = 1; k <= 256; ++k) ASSERT_TRUE(m.phase->deliver(remote_packet(1000 + k, {-1.0, 0, 0}), 0));
  m.phase->peer_changed();                                            // no room: it waits
  EXPECT_FALSE(m.phase->deliver(remote_packet(1, {-2.0, 0, 0}), 0));  // behind it: dropped, counted
  m.device.cycle(cycle_at(0), 1.0);                                   // takes the old peer's packets
  ASSERT_TRUE(m.phase->deliver(remote_packet(2, {-2.0, 0, 0}), 0));   // the change, then the new peer's packet
  m.device.cycle(cycle_at(1), 1.0);
  TeleopReport r;
  ASSERT_TRUE(m.phase->take_report(r));
  EXPECT_EQ(r.received, 257u) << "the new peer's packet was taken as stale";
  EXPECT_EQ(r.dropped, 1u);
  EXPECT_NEAR(m.device.published_snapshot().engine_wrench.force.x(), -2.0, 1e-9);
}

TEST(TeleopPhase, TheCycleNeverAllocatesWithPacketsFlowingBothWays) {
  MasterSide m;
  for (std::uint64_t k = 0; k < 50; ++k) {  // warm up: the link comes up
    m.phase->deliver(remote_packet(k + 1, {-1.0, 0, 0}), cycle_at(k).time_ns);
    m.device.cycle(cycle_at(k), 1.0);
  }
  teleop::LinkPacket out;
  TeleopReport r;
  testing::AllocationGuard guard;
  for (std::uint64_t k = 50; k < 2050; ++k) {
    m.phase->deliver(remote_packet(k + 1, {-1.0 - 1e-3 * static_cast<double>(k % 7), 0, 0}), cycle_at(k).time_ns);
    m.device.cycle(cycle_at(k), 1.0);
    (void)m.phase->take_outgoing(out);
    (void)m.phase->take_report(r);
  }
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_EQ(r.received, 2050u);
}

}  // namespace
}  // namespace hapticd::server
