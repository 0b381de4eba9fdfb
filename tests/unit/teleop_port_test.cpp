// The link's policies (teleop/teleop_port.hpp, docs/teleoperation.md "Safety"), the one place both the server's
// TeleopLink and the evaluation take them from: the peer's stop stops this side once per stop; a silent link stops
// the remote and fades the master (and says so once, and again when it is back); a recovered side goes on from
// where its handle is; no force while stopped or ending; a cycle never allocates.
#include "hapticd/teleop/teleop_port.hpp"

#include <gtest/gtest.h>

#include <string_view>

#include "hapticd/testing/allocation_guard.hpp"

namespace hapticd::teleop {
namespace {

constexpr std::int64_t kMs = 1'000'000;

LocalSample at(std::int64_t ms, double x) {
  LocalSample s;
  s.time_ns = ms * kMs;
  s.position = {x, 0, 0};
  return s;
}

LinkPacket from_peer(std::uint64_t sequence, double x, bool stopped = false) {
  LinkPacket p;
  p.sequence = sequence;
  p.position = {x, 0, 0};
  p.stopped = stopped;
  return p;
}

LinkSettings settings() {
  LinkSettings s;
  s.architecture = Architecture::position_position;
  s.passivity = Passivity::none;
  s.link_timeout_s = 0.2;
  return s;
}

TEST(TeleopPort, ThePeersStopStopsThisSideOncePerStop) {
  TeleopPort port(Role::master, settings());
  port.receive(from_peer(1, 0.0), 0);
  EXPECT_EQ(port.cycle(at(1, 0.0), 1e-3, false, false).stop, PortStop::none);
  port.receive(from_peer(2, 0.0, true), 2 * kMs);
  const PortCycle c = port.cycle(at(2, 0.0), 1e-3, false, false);
  EXPECT_EQ(c.stop, PortStop::peer_stopped);
  EXPECT_EQ(std::string_view(stop_code(c.stop)), "teleoperation_peer_stopped");
  EXPECT_FALSE(c.apply);
  // While the peer stays stopped, this side (stopped, then recovered before the peer) is not stopped again.
  EXPECT_EQ(port.cycle(at(3, 0.0), 1e-3, true, false).stop, PortStop::none);
  port.receive(from_peer(3, 0.0, true), 4 * kMs);
  EXPECT_EQ(port.cycle(at(4, 0.0), 1e-3, false, false).stop, PortStop::none);
  // The peer runs again, then stops again: this side stops again.
  port.receive(from_peer(4, 0.0), 5 * kMs);
  EXPECT_EQ(port.cycle(at(5, 0.0), 1e-3, false, false).stop, PortStop::none);
  port.receive(from_peer(5, 0.0, true), 6 * kMs);
  EXPECT_EQ(port.cycle(at(6, 0.0), 1e-3, false, false).stop, PortStop::peer_stopped);
}

TEST(TeleopPort, ASilentLinkStopsTheRemoteAndFadesTheMaster) {
  for (const Role role : {Role::master, Role::remote}) {
    TeleopPort port(role, settings());
    port.receive(from_peer(1, 0.0), 0);
    int stops = 0, losses = 0, backs = 0;
    for (int k = 1; k <= 400; ++k) {
      const PortCycle c = port.cycle(at(k, 0.0), 1e-3, false, false);
      stops += c.stop != PortStop::none ? 1 : 0;
      losses += c.lost ? 1 : 0;
      if (c.stop != PortStop::none) EXPECT_EQ(std::string_view(stop_code(c.stop)), "teleoperation_link_lost");
    }
    EXPECT_EQ(losses, 1);
    EXPECT_EQ(stops, role == Role::remote ? 1 : 0);
    port.receive(from_peer(2, 0.0), 401 * kMs);
    for (int k = 401; k <= 410; ++k) backs += port.cycle(at(k, 0.0), 1e-3, false, false).back ? 1 : 0;
    EXPECT_EQ(backs, 1);
  }
}

TEST(TeleopPort, ARecoveredSideGoesOnFromWhereItsHandleIs) {
  LinkSettings s = settings();
  s.stiffness = 1000.0;
  s.damping = 0.0;
  TeleopPort port(Role::master, s);
  port.receive(from_peer(1, 0.0), 0);
  port.cycle(at(1, 0.0), 1e-3, false, false);
  // Stopped while the handle is carried 5 cm away; recovered there: no pull back towards the peer.
  for (int k = 2; k < 100; ++k) EXPECT_FALSE(port.cycle(at(k, 0.05), 1e-3, true, false).apply);
  const PortCycle c = port.cycle(at(100, 0.05), 1e-3, false, false);
  EXPECT_TRUE(c.apply);
  EXPECT_NEAR(c.force.norm(), 0.0, 1e-9);
}

TEST(TeleopPort, NoForceWhileTheSessionEndsAndNoAllocation) {
  TeleopPort port(Role::remote, settings());
  port.receive(from_peer(1, 0.01), 0);
  port.cycle(at(1, 0.0), 1e-3, false, false);
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "the sanitizer owns malloc";
  testing::AllocationGuard guard;
  PortCycle c;
  for (int k = 2; k < 50; ++k) {
    port.receive(from_peer(static_cast<std::uint64_t>(k), 0.01), k * kMs);
    c = port.cycle(at(k, 0.0), 1e-3, false, true);
  }
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_FALSE(c.apply);
  EXPECT_EQ(c.stop, PortStop::none);
  EXPECT_GT(c.force.norm(), 1.0);  // the link's pull is computed (and reported), only not applied
}

}  // namespace
}  // namespace hapticd::teleop
