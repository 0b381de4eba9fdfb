// The teleoperation link's pieces without a device: the channel model (delay, jitter, loss, reordering, by seed),
// the time-domain passivity port, and one side's control laws, link loss and stop (docs/teleoperation.md).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "hapticd/teleop/channel_model.hpp"
#include "hapticd/teleop/energy_port.hpp"
#include "hapticd/teleop/teleop_side.hpp"
#include "hapticd/testing/allocation_guard.hpp"

namespace hapticd::teleop {
namespace {

constexpr std::int64_t kMs = 1'000'000;

LinkPacket packet(std::uint64_t seq) {
  LinkPacket p;
  p.sequence = seq;
  p.position.x() = static_cast<double>(seq);
  return p;
}

// Sends one packet per millisecond for `n` ms and returns (arrival ms, sequence) of what arrived by `until` ms.
std::vector<std::pair<std::int64_t, std::uint64_t>> run_channel(ChannelModel& c, int n, int until) {
  std::vector<std::pair<std::int64_t, std::uint64_t>> got;
  for (int ms = 0; ms <= until; ++ms) {
    c.deliver(ms * kMs, [&](const LinkPacket& p) { got.emplace_back(ms, p.sequence); });
    if (ms < n) c.send(packet(static_cast<std::uint64_t>(ms + 1)), ms * kMs);
  }
  return got;
}

TEST(ChannelModel, DelaysEveryPacketByTheDelay) {
  ChannelModel c({.delay_s = 0.025});
  const auto got = run_channel(c, 100, 200);
  ASSERT_EQ(got.size(), 100u);
  for (const auto& [arrived, seq] : got) EXPECT_EQ(arrived, static_cast<std::int64_t>(seq) - 1 + 25);
  EXPECT_EQ(c.counters().reordered, 0u);
}

TEST(ChannelModel, LosesTheGivenShareAndTheSameSeedLosesTheSamePackets) {
  ChannelModel a({.delay_s = 0.01, .loss = 0.2, .seed = 7});
  ChannelModel b({.delay_s = 0.01, .loss = 0.2, .seed = 7});
  ChannelModel other({.delay_s = 0.01, .loss = 0.2, .seed = 8});
  const auto ga = run_channel(a, 5000, 5100);
  EXPECT_EQ(ga, run_channel(b, 5000, 5100));
  EXPECT_NE(ga, run_channel(other, 5000, 5100));
  EXPECT_NEAR(static_cast<double>(a.counters().lost) / 5000.0, 0.2, 0.02);
  EXPECT_EQ(a.counters().delivered + a.counters().lost, 5000u);
}

TEST(ChannelModel, JitterReordersAndDelaysWithinItsBounds) {
  ChannelModel c({.delay_s = 0.02, .jitter_s = 0.01, .seed = 3});
  const auto got = run_channel(c, 1000, 1100);
  ASSERT_EQ(got.size(), 1000u);
  for (const auto& [arrived, seq] : got) {
    const std::int64_t sent = static_cast<std::int64_t>(seq) - 1;
    EXPECT_GE(arrived - sent, 20);
    EXPECT_LE(arrived - sent, 31);  // delivered at the first millisecond after its arrival
  }
  EXPECT_GT(c.counters().reordered, 100u);
}

TEST(ChannelModel, VaryingDelayStaysWithinItsRange) {
  ChannelModel c({.delay_s = 0.1, .delay_variation_s = 0.05, .variation_period_s = 0.5});
  const auto got = run_channel(c, 2000, 2300);
  std::int64_t lo = 1000, hi = 0;
  for (const auto& [arrived, seq] : got) {
    lo = std::min(lo, arrived - static_cast<std::int64_t>(seq) + 1);
    hi = std::max(hi, arrived - static_cast<std::int64_t>(seq) + 1);
  }
  EXPECT_NEAR(static_cast<double>(lo), 50.0, 2.0);
  EXPECT_NEAR(static_cast<double>(hi), 150.0, 2.0);
}

TEST(ChannelModel, RefusesBadSettingsAndNeverAllocatesOnceBuilt) {
  EXPECT_THROW(ChannelModel({.delay_s = -1.0}), std::invalid_argument);
  EXPECT_THROW(ChannelModel({.loss = 1.0}), std::invalid_argument);
  EXPECT_THROW(ChannelModel({.delay_s = 0.01, .delay_variation_s = 0.02}), std::invalid_argument);
  EXPECT_THROW(ChannelModel({.jitter_s = std::nan("")}), std::invalid_argument);
  ChannelModel c({.delay_s = 0.5, .jitter_s = 0.1, .loss = 0.1});
  testing::AllocationGuard guard;
  std::uint64_t n = 0;
  for (int ms = 0; ms < 3000; ++ms) {
    c.send(packet(static_cast<std::uint64_t>(ms + 1)), ms * kMs);
    c.deliver(ms * kMs, [&](const LinkPacket&) { ++n; });
  }
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_GT(n, 2000u);
}

TEST(EnergyPort, NeverLetsMoreEnergyOutThanCameInAtTheOtherPort) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  EnergyPort port;
  double available = 0.0;
  for (int k = 0; k < 20000; ++k) {
    available += std::max(0.0, u(rng)) * 1e-3;  // the other port's energy in, growing in fits
    const Eigen::Vector3d f(10 * u(rng), 10 * u(rng), 10 * u(rng));
    const Eigen::Vector3d v(u(rng), u(rng), u(rng));
    const Eigen::Vector3d applied = port.force_out(f, v, 1e-3, available, true);
    EXPECT_LE(applied.norm(), f.norm() + 1e-9);
    ASSERT_LE(port.energy_out(), available + 1e-12) << "step " << k;
  }
  EXPECT_GT(port.dissipated(), 0.0);
  EXPECT_GE(port.observed(), -1e-12);
}

TEST(EnergyPort, AtAVelocityPortTheDamperActsInParallel) {
  EnergyPort port;
  // The local side pushes back with 10 N against a commanded 0.1 m/s: 1 W out; nothing came in.
  const Eigen::Vector3d v = port.velocity_out({0.1, 0, 0}, {-10, 0, 0}, 1e-3, 0.0, true);
  EXPECT_NEAR(v.x(), 0.0, 1e-12);
  EXPECT_TRUE(port.limiting());
  // With 0.5 mJ in, half the step's power goes through.
  EnergyPort paid;
  const Eigen::Vector3d half = paid.velocity_out({0.1, 0, 0}, {-10, 0, 0}, 1e-3, 0.5e-3, true);
  EXPECT_NEAR(half.x(), 0.05, 1e-12);
  EXPECT_NEAR(paid.energy_out(), 0.5e-3, 1e-15);
  // Observing only: the energy out is counted, the velocity untouched.
  EnergyPort watch;
  EXPECT_NEAR(watch.velocity_out({0.1, 0, 0}, {-10, 0, 0}, 1e-3, 0.0, false).x(), 0.1, 1e-12);
  EXPECT_LT(watch.observed(), 0.0);
}

LocalSample at(std::int64_t ms, double x, double v = 0.0, double f = 0.0) {
  LocalSample s;
  s.time_ns = ms * kMs;
  s.position = {x, 0, 0};
  s.velocity = {v, 0, 0};
  s.force = {f, 0, 0};
  return s;
}

TEST(TeleopSide, RefusesBadSettingsWithTheirNames) {
  LinkSettings s;
  s.passivity = Passivity::wave;
  s.architecture = Architecture::position_position;
  EXPECT_NE(link_settings_problem(s).find("wave"), std::string::npos);
  EXPECT_THROW(TeleopSide(Role::master, s), std::invalid_argument);
  LinkSettings k;
  k.stiffness = -1.0;
  EXPECT_NE(link_settings_problem(k).find("stiffness"), std::string::npos);
  LinkSettings t;
  t.link_timeout_s = std::nan("");
  EXPECT_NE(link_settings_problem(t).find("link_timeout_s"), std::string::npos);
}

TEST(TeleopSide, PositionForceRemoteFollowsTheMasterAndMasterDisplaysTheRemotesForce) {
  LinkSettings s;
  s.passivity = Passivity::none;
  s.force_scale = 2.0;
  TeleopSide master(Role::master, s), remote(Role::remote, s);
  master.start(at(0, 0.5));
  remote.start(at(0, -0.2));
  // The master moved 1 cm: the remote's setpoint goes there and its spring pulls the handle.
  const SideOutput m = master.cycle(at(1, 0.51, 0.0), 1e-3);
  EXPECT_NEAR(m.packet.position.x(), 0.01, 1e-12);
  remote.receive(m.packet);
  SideOutput r;
  for (int k = 2; k < 200; ++k) r = remote.cycle(at(k, -0.2), 1e-3);
  EXPECT_NEAR(remote.setpoint().x(), 0.01, 1e-4);
  EXPECT_NEAR(r.force.x(), s.stiffness * 0.01, 0.2);
  // The remote's environment pushes back with 3 N: the master shows 6 N (force_scale 2).
  r = remote.cycle(at(200, -0.2, 0.0, -3.0), 1e-3);
  master.receive(r.packet);
  EXPECT_NEAR(master.cycle(at(201, 0.51), 1e-3).force.x(), -6.0, 1e-9);
}

TEST(TeleopSide, ScalesMotionAndForceAndConvertsTheEnergiesBetweenThem) {
  LinkSettings s;
  s.motion_scale = 0.5;  // the remote moves half the master's motion
  s.force_scale = 2.0;   // the master feels twice the remote's force
  TeleopSide master(Role::master, s), remote(Role::remote, s);
  master.start(at(0, 0.0));
  remote.start(at(0, 0.0));
  const SideOutput m = master.cycle(at(1, 0.02, 0.1), 1e-3);
  EXPECT_NEAR(m.packet.position.x(), 0.01, 1e-12);
  EXPECT_NEAR(m.packet.velocity.x(), 0.05, 1e-12);
  // Power scales by force_scale / motion_scale = 4 from the remote's units to the master's: 1 J in at the remote
  // pays for 4 J out at the master, and 1 J in at the master for 0.25 J out at the remote.
  const auto one_joule_in = [] {
    LinkPacket p;
    p.sequence = 1;
    p.energy_in = 1.0;
    return p;
  };
  master.receive(one_joule_in());
  master.cycle(at(2, 0.02), 1e-3);
  EXPECT_NEAR(master.status().peer_energy_in, 4.0, 1e-12);
  remote.receive(one_joule_in());
  remote.cycle(at(2, 0.0), 1e-3);
  EXPECT_NEAR(remote.status().peer_energy_in, 0.25, 1e-12);
}

TEST(TeleopSide, TdpaStopsTheRemoteSetpointUntilTheMasterHasPaidForTheContact) {
  LinkSettings s;  // tdpa
  TeleopSide remote(Role::remote, s);
  remote.start(at(0, 0.0));
  LinkPacket from_master;
  from_master.sequence = 1;
  from_master.position = {0.02, 0, 0};  // the master is 2 cm ahead, having put no energy in
  from_master.velocity = {0.05, 0, 0};  // moving: the energy it reports later is energy its motion could carry
  remote.receive(from_master);
  // In contact: the environment pushes back on the handle; the setpoint may not advance into it.
  for (int k = 1; k < 100; ++k) remote.cycle(at(k, 0.0, 0.0, -5.0), 1e-3);
  EXPECT_NEAR(remote.setpoint().x(), 0.0, 1e-9);
  EXPECT_NEAR(remote.status().port->energy_out(), 0.0, 1e-12);
  // 10 mJ arrive: the setpoint advances by what 10 mJ pay against 5 N, 2 mm.
  from_master.sequence = 2;
  from_master.energy_in = 0.01;
  remote.receive(from_master);
  for (int k = 100; k < 400; ++k) remote.cycle(at(k, 0.0, 0.0, -5.0), 1e-3);
  EXPECT_NEAR(remote.setpoint().x(), 0.002, 1e-6);
  EXPECT_NEAR(remote.status().port->energy_out(), 0.01, 1e-9);
}

TEST(TeleopSide, ALostLinkHoldsTheRemoteAndFadesTheMastersForce) {
  LinkSettings s;
  s.passivity = Passivity::none;
  s.link_timeout_s = 0.2;
  s.fade_s = 0.1;
  TeleopSide master(Role::master, s), remote(Role::remote, s);
  master.start(at(0, 0.0));
  remote.start(at(0, 0.0));
  LinkPacket from_remote;
  from_remote.sequence = 1;
  from_remote.force = {-4.0, 0, 0};
  master.receive(from_remote);
  LinkPacket from_master;
  from_master.sequence = 1;
  from_master.velocity = {0.1, 0, 0};
  from_master.position = {0.05, 0, 0};
  remote.receive(from_master);
  EXPECT_NEAR(master.cycle(at(1, 0.0), 1e-3).force.x(), -4.0, 1e-12);
  // Silence: after 0.2 s the link is lost; the master's force is gone 0.1 s later; the remote's setpoint stops.
  SideOutput m;
  for (int k = 2; k <= 250; ++k) {
    m = master.cycle(at(k, 0.0), 1e-3);
    remote.cycle(at(k, 0.0), 1e-3);
  }
  EXPECT_TRUE(master.status().link_lost);
  EXPECT_TRUE(remote.status().link_lost);
  const Eigen::Vector3d held = remote.setpoint();
  for (int k = 251; k <= 400; ++k) {
    m = master.cycle(at(k, 0.0), 1e-3);
    remote.cycle(at(k, 0.0), 1e-3);
  }
  EXPECT_EQ(m.force.norm(), 0.0);
  EXPECT_EQ(remote.setpoint(), held);
  // The link comes back: the master's force returns over the fade time.
  from_remote.sequence = 2;
  master.receive(from_remote);
  EXPECT_NEAR(master.cycle(at(401, 0.0), 1e-3).force.x(), -0.04, 1e-9);
  for (int k = 402; k <= 500; ++k) m = master.cycle(at(k, 0.0), 1e-3);
  EXPECT_NEAR(m.force.x(), -4.0, 1e-9);
}

TEST(TeleopSide, EitherSidesStopStopsTheOther) {
  LinkSettings s;
  s.passivity = Passivity::none;
  TeleopSide master(Role::master, s), remote(Role::remote, s);
  master.start(at(0, 0.0));
  remote.start(at(0, 0.0));
  // The master is stopped (its E-stop): its packets say so; the remote's setpoint stops following.
  SideOutput m = master.cycle(at(1, 0.01, 0.1), 1e-3, true);
  EXPECT_TRUE(m.packet.stopped);
  remote.receive(m.packet);
  for (int k = 2; k < 50; ++k) remote.cycle(at(k, 0.0), 1e-3);
  EXPECT_TRUE(remote.status().peer_stopped);
  EXPECT_EQ(remote.setpoint().norm(), 0.0);
  // The remote is stopped: the master's force fades.
  LinkPacket r;
  r.sequence = 1;
  r.force = {-2.0, 0, 0};
  r.stopped = true;
  master.receive(r);
  for (int k = 50; k < 200; ++k) m = master.cycle(at(k, 0.0), 1e-3);
  EXPECT_TRUE(master.status().peer_stopped);
  EXPECT_EQ(m.force.norm(), 0.0);
}

TEST(TeleopSide, KeepsOnlyTheNewestPacketAndNeverAllocates) {
  LinkSettings s;
  s.passivity = Passivity::none;
  TeleopSide master(Role::master, s);
  master.start(at(0, 0.0));
  LinkPacket p;
  p.sequence = 5;
  p.force = {-1.0, 0, 0};
  master.receive(p);
  p.sequence = 4;  // late
  p.force = {-9.0, 0, 0};
  master.receive(p);
  EXPECT_EQ(master.status().stale, 1u);
  testing::AllocationGuard guard;
  SideOutput out;
  for (int k = 1; k < 1000; ++k) out = master.cycle(at(k, 0.001 * k, 1.0), 1e-3);
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_NEAR(out.force.x(), -1.0, 1e-12);
}

// A link that never came up is waiting, not lost: a pair whose discovery took longer than the timeout (a soak
// through the relay on a loaded machine) stopped its remote at start. The remote holds; once packets came and
// stop, the link is lost as before.
TEST(TeleopSide, ALinkThatNeverCameUpWaitsAndIsLostOnlyAfterItsFirstPacket) {
  LinkSettings s;
  s.link_timeout_s = 0.2;
  TeleopSide remote(Role::remote, s);
  remote.start(at(0, 0.0));
  for (int k = 1; k <= 500; ++k) remote.cycle(at(k, 0.0), 1e-3);
  EXPECT_TRUE(remote.status().waiting);
  EXPECT_FALSE(remote.status().link_lost);
  EXPECT_EQ(remote.setpoint(), Eigen::Vector3d::Zero());
  remote.receive(packet(1));
  remote.cycle(at(501, 0.0), 1e-3);
  EXPECT_FALSE(remote.status().waiting);
  for (int k = 502; k <= 800; ++k) remote.cycle(at(k, 0.0), 1e-3);
  EXPECT_TRUE(remote.status().link_lost);
}

// Hardening round 4, item 3: a forged serial of 2^64-1 made every later packet "older" for good. Serial-number
// arithmetic: a serial far ahead is older; a wrapping serial goes on.
TEST(TeleopSide, SerialsCompareBySerialArithmetic) {
  LinkSettings s;
  s.passivity = Passivity::none;
  TeleopSide master(Role::master, s);
  master.start(at(0, 0.0));
  master.receive(packet(100));
  master.receive(packet(~std::uint64_t{0}));  // 2^64-1 after 100: older by serial arithmetic
  EXPECT_EQ(master.status().stale, 1u);
  master.receive(packet(101));
  EXPECT_EQ(master.status().received, 2u);
  TeleopSide wrapping(Role::master, s);
  wrapping.start(at(0, 0.0));
  wrapping.receive(packet(~std::uint64_t{0} - 1));
  wrapping.receive(packet(~std::uint64_t{0}));
  wrapping.receive(packet(1));  // the count wrapped: newer
  EXPECT_EQ(wrapping.status().received, 3u);
  EXPECT_EQ(wrapping.status().stale, 0u);
}

// Item 2: a peer's claimed energy was taken on trust (1e9 J let a forger's force through the passivity controller).
// Credited only as far as the force and motion at the peer's port could carry it: the remote's port takes in at
// most its environment's force times the setpoint's speed limit, the master's the link's force times its speed.
TEST(TeleopSide, APeersEnergyIsCreditedOnlyAsFarAsTheLinksForceAndMotionCouldCarryIt) {
  LinkSettings s;  // tdpa, max_force 40 N, max_speed 1 m/s
  TeleopSide master(Role::master, s);
  master.start(at(0, 0.0));
  LinkPacket from_remote;
  from_remote.energy_in = 1e9;
  from_remote.force = {-10.0, 0, 0};  // displayed by the master; at rest it carries no energy
  for (int k = 1; k <= 500; ++k) {
    from_remote.sequence = static_cast<std::uint64_t>(k);
    from_remote.force = k <= 250 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(-10.0, 0, 0);
    master.receive(from_remote);
    // The operator's hand moves with the force: energy out of the link, paid only from what is credited.
    master.cycle(at(k, -1e-4 * k, -0.1), 1e-3);
    if (k == 250) {
      EXPECT_EQ(master.status().peer_energy_credited, 0.0);  // no force at the remote's port: nothing carried
      EXPECT_NEAR(master.status().peer_energy_in, 1e9, 1.0);
    }
  }
  // 10 N for 0.25 s at up to 1 m/s, twice: at most 5 J credited; the controller let out no more.
  EXPECT_GT(master.status().peer_energy_credited, 4.0);
  EXPECT_LE(master.status().peer_energy_credited, 5.0 + 1e-9);
  EXPECT_LE(master.status().port->energy_out(), master.status().peer_energy_credited + 1e-9);

  TeleopSide remote(Role::remote, s);
  remote.start(at(0, 0.0));
  LinkPacket from_master;
  from_master.energy_in = 1e9;
  from_master.velocity = {0.05, 0, 0};
  for (int k = 1; k <= 200; ++k) {
    from_master.sequence = static_cast<std::uint64_t>(k);
    remote.receive(from_master);
    remote.cycle(at(k, 0.0, 0.0, -5.0), 1e-3);
  }
  // The master's port: 40 N at 0.05 m/s, twice, for 0.2 s: 0.8 J.
  EXPECT_NEAR(remote.status().peer_energy_credited, 0.8, 0.01);
}

// Item 3: a restarted peer (its server's new participant; serials from 1 again) was ignored for good. After
// peer_changed its packets are taken, its energy counts from zero on top of what was credited, and the side
// re-anchors where its handle is: no pull towards where the new peer's motion starts.
TEST(TeleopSide, ANewPeerStartsItsSerialsAndEnergyAfreshAndTheSideReanchors) {
  LinkSettings s;
  s.passivity = Passivity::none;
  TeleopSide remote(Role::remote, s);
  remote.start(at(0, 0.0));
  LinkPacket p;
  p.position = {0.01, 0, 0};
  for (int k = 1; k <= 500; ++k) {
    p.sequence = static_cast<std::uint64_t>(k);
    remote.receive(p);
    remote.cycle(at(k, 0.01), 1e-3);
  }
  EXPECT_NEAR(remote.setpoint().x(), 0.01, 1e-4);
  p.sequence = 1;
  p.position = {0.0, 0, 0};  // the new master starts where its own handle is: 0
  remote.receive(p);
  EXPECT_EQ(remote.status().stale, 1u);  // the old sender's count: older
  remote.peer_changed();
  remote.receive(p);
  EXPECT_EQ(remote.status().received, 501u);
  EXPECT_EQ(remote.status().peers, 2u);
  SideOutput out;
  for (int k = 501; k <= 700; ++k) out = remote.cycle(at(k, 0.01), 1e-3);
  EXPECT_LT(out.force.norm(), 0.1) << "the remote is pulled towards the new master's start";
  // The new master moves 1 cm: the remote follows from where it is.
  p.sequence = 2;
  p.position = {0.01, 0, 0};
  remote.receive(p);
  for (int k = 701; k <= 900; ++k) out = remote.cycle(at(k, 0.01), 1e-3);
  EXPECT_NEAR(out.force.x(), s.stiffness * 0.01, 0.5);
}

}  // namespace
}  // namespace hapticd::teleop
