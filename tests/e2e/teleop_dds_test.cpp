// The teleoperation link over DDS (doors/teleop/teleop_link, docs/teleoperation.md): one side served here as `hapticd`
// serves it, the other written with raw DDS as another server's link would write it (and as an attacker could):
// the remote follows the master's motion into its wall and reports the contact; the link holds the device's claim;
// malformed packets are rejected, counted and never applied; a silent link stops the remote and fades the master's
// force; the peer's stop stops this side. Loopback, domains 155 and 156, each test bounded in time.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>

#include "e2e/dds_server_rig.hpp"
#include "hapticd/dds/conversion.hpp"
#include "support/test_paths.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using namespace std::chrono_literals;
using e2e::Server;

std::string side_yaml(int domain, double duration_s, const std::string& role, const std::string& device,
                      const std::string& peer, const std::string& attachment, const std::string& passivity) {
  return "server: {clock: realtime, rate_hz: 1000, seed: 5, realtime_priority: 0, lock_memory: false, duration_s: " +
         std::to_string(duration_s) + "}\ndds: {domain_id: " + std::to_string(domain) +
         "}\nteleoperation: {role: " + role + ", peer: " + peer + ", passivity: " + passivity +
         ", link_timeout_s: 0.3, fade_s: 0.05}\ndevices:\n  - name: " + device +
         "\n    device:\n      plugin: sim\n      parameters: {urdf: " + test::source_dir() +
         "/config/urdf/vishard3.urdf, initial_position: [-0.3, 1.6, 0.0], passive_gimbal: true, " + attachment +
         "}\n    virtual_model:\n      plugin: admittance\n      parameters: {mass_kg: [3.0, 3.0, 3.0], "
         "damping_n_s_per_m: [15.0, 15.0, 15.0], rotation: false, coupling: true, coupling_stiffness_n_per_m: 0, "
         "coupling_damping_n_s_per_m: 0}\n    controller:\n      plugin: resolved_acceleration\n      parameters: "
         "{task: translation, bandwidth_rad_s: 60}\n    safety: {" +
         e2e::kRealtimeWatchdogs + "}\n";
}

// The other server's side, written by hand: sends its packets at 1 kHz on a thread of its own, takes the served
// side's. As a server's link does, it writes in its device's partition and reads its peer's (data model 13).
class Peer {
 public:
  Peer(int domain, const std::string& me, const std::string& to, std::int32_t role)
      : participant_(dds::ParticipantOptions{domain, {}, {}}),
        writer_(participant_, {}, "hapticd.teleop." + me),
        reader_(participant_, {}, nullptr, {"hapticd.teleop." + to}) {
    dds::set_text(packet_.sender, me);
    dds::set_text(packet_.receiver, to);
    packet_.role = role;
    packet_.orientation[0] = 1.0;  // identity: a translation-only link's
    packet_.energy_in = 1000.0;    // plenty: the served side's passivity controller never has to act for want of it
  }
  ~Peer() { stop(); }
  // The packet to send from now on (the serial is the peer's); `bad`: every 10th packet is replaced by it.
  void set(const std::function<void(hapticd_msg_TeleopPacket&, double t)>& motion) {
    std::lock_guard lock(mutex_);
    motion_ = motion;
  }
  void set_bad(const std::vector<hapticd_msg_TeleopPacket>& bad) {
    std::lock_guard lock(mutex_);
    bad_ = bad;
  }
  void start() {
    running_ = true;
    thread_ = std::thread([this] { run(); });
  }
  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }
  std::uint64_t bad_sent() const { return bad_sent_.load(); }
  // The peer's count goes on from here (an impostor's serials ahead of the real peer's).
  void count_from(std::uint64_t serial) {
    std::lock_guard lock(mutex_);
    serial_ = serial - 1;
  }
  // One packet goes out with this serial (a forged one; the peer's own count goes on after it).
  void forge_serial(std::uint64_t serial) {
    std::lock_guard lock(mutex_);
    forged_ = serial;
  }
  // The served side's newest packet (serial 0: none yet).
  hapticd_msg_TeleopPacket newest() {
    reader_.take([&](const hapticd_msg_TeleopPacket& p, const dds_sample_info_t&) {
      if (dds::text_of(p.sender) == dds::text_of(packet_.receiver) && p.serial > newest_.serial) newest_ = p;
    });
    return newest_;
  }
  bool wait_matched(std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (writer_.matched() == 0 && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(5ms);
    return writer_.matched() > 0;
  }

 private:
  void run() {
    const auto start = std::chrono::steady_clock::now();
    std::uint64_t k = 0;
    while (running_) {
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      {
        std::lock_guard lock(mutex_);
        packet_.serial = forged_ != 0 ? forged_ : ++serial_;
        forged_ = 0;
        packet_.sent_ns = static_cast<std::int64_t>(t * 1e9);
        if (motion_) motion_(packet_, t);
        if (!bad_.empty() && ++k % 10 == 0) {
          hapticd_msg_TeleopPacket b = bad_[(k / 10) % bad_.size()];
          b.serial = packet_.serial;
          (void)writer_.write(b);
          bad_sent_.fetch_add(1);
        } else {
          (void)writer_.write(packet_);
        }
      }
      std::this_thread::sleep_for(1ms);
    }
  }
  dds::Participant participant_;
  dds::Writer<hapticd_msg_TeleopPacket> writer_;
  dds::Reader<hapticd_msg_TeleopPacket> reader_;
  std::mutex mutex_;
  hapticd_msg_TeleopPacket packet_{};
  hapticd_msg_TeleopPacket newest_{};
  std::function<void(hapticd_msg_TeleopPacket&, double)> motion_;
  std::vector<hapticd_msg_TeleopPacket> bad_;
  std::uint64_t serial_ = 0;
  std::uint64_t forged_ = 0;
  std::atomic<std::uint64_t> bad_sent_{0};
  std::atomic<bool> running_{false};
  std::thread thread_;
};

bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(10ms);
  }
  return true;
}

// A link in six degrees of freedom needs a device that can render its torques: a ViSHaRD3 (three joints, a passive
// gimbal) is refused at start, naming the key and the device.
TEST(TeleopLink, RotationOnADeviceWithoutTorquesIsRefusedAtStart) {
  std::string yaml = side_yaml(156, 1.0, "master", "master", "remote", "attachment: none", "tdpa");
  yaml.replace(yaml.find("link_timeout_s"), 0, "rotation: true, ");
  try {
    Server server(yaml);
    FAIL() << "a ViSHaRD3 took a link with rotation";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("teleoperation.rotation: device 'master' has 3 joints"), std::string::npos)
        << e.what();
  }
}

TEST(TeleopLink, TheRemoteFollowsIntoItsWallRejectsMalformedPacketsAndStopsWhenTheLinkFallsSilent) {
  constexpr int kDomain = 155;
  Server server(side_yaml(kDomain, 8.0, "remote", "remote", "master",
                          "attachment: none, wall_normal: [1.0, 0.0, 0.0], wall_offset_m: 0.03", "tdpa"));
  Peer master(kDomain, "master", "remote", hapticd_msg_TELEOP_MASTER);
  // The master's hand moves 5 cm along x over 1 s and holds: 2 cm past the remote's wall.
  master.set([](hapticd_msg_TeleopPacket& p, double t) {
    const double s = std::clamp(t - 0.5, 0.0, 1.0);
    p.position[0] = 0.05 * s;
    p.velocity[0] = s > 0.0 && s < 1.0 ? 0.05 : 0.0;
    p.energy_in = 1000.0;
  });
  // Malformed, or not for this link: each is rejected and counted, never applied.
  std::vector<hapticd_msg_TeleopPacket> bad(7);
  for (auto& b : bad) {
    dds::set_text(b.sender, "master");
    dds::set_text(b.receiver, "remote");
    b.role = hapticd_msg_TELEOP_MASTER;
    b.orientation[0] = 1.0;
  }
  bad[0].position[0] = std::nan("");        // not finite
  bad[1].position[0] = 1e6;                 // out of range
  bad[2].role = hapticd_msg_TELEOP_REMOTE;  // the same role as the served side
  bad[3].energy_in = -5.0;
  dds::set_text(bad[4].sender, "intruder");               // another device
  std::memset(bad[5].sender, 'x', sizeof bad[5].sender);  // not terminated
  bad[6].orientation[0] = 3.0;                            // not a unit quaternion
  master.set_bad(bad);
  server.start();
  ASSERT_TRUE(master.wait_matched(20s));
  master.start();

  // A DDS engine cannot claim the linked device: the link holds it.
  client::Client engine({"intruding-engine", kDomain});
  ASSERT_TRUE(engine.wait_for_device("remote", 20s).has_value());
  EXPECT_FALSE(engine.claim("remote", 5s).accepted);

  std::this_thread::sleep_for(2500ms);
  const hapticd_msg_TeleopPacket r = master.newest();
  ASSERT_GT(r.serial, 1000u);
  EXPECT_EQ(server.device().status().fault(), DeviceFault::none);
  // At its wall (3 cm ahead, 5000 N/m) with the position controller's spring 2 cm short of the master.
  EXPECT_GT(r.position[0], 0.028) << r.position[0];
  EXPECT_LT(r.position[0], 0.040) << r.position[0];
  EXPECT_LT(r.force[0], -5.0) << "the wall's force on the remote: " << r.force[0];
  EXPECT_FALSE(r.stopped);
  const TeleopLink& link = *server.bridge().teleop_link();
  EXPECT_GT(link.packets_taken(), 1500u);
  EXPECT_GE(link.packets_rejected(), master.bad_sent() * 9 / 10) << "of " << master.bad_sent();
  EXPECT_GT(master.bad_sent(), 100u);

  // The master falls silent: after 0.3 s the remote stops (an emergency stop) and says so in its packets.
  master.stop();
  EXPECT_TRUE(wait_until([&] { return server.device().status().fault() == DeviceFault::emergency_stop; }, 2000ms))
      << to_string(server.device().status().fault());
  EXPECT_EQ(link.stops(), 1u);
  EXPECT_EQ(link.losses(), 1u);
  EXPECT_TRUE(wait_until([&] { return master.newest().stopped; }, 1000ms));
  // The person at the device recovers it (the link, which holds the claim, cannot ask): any client may.
  const auto reply = engine.recover("remote", 5s);
  EXPECT_TRUE(reply.accepted) << reply.message;
  server.join();  // the session's duration
}

TEST(TeleopLink, TheMasterDisplaysTheRemotesForceFadesItWhenTheLinkIsSilentAndStopsWithTheRemote) {
  constexpr int kDomain = 156;
  Server server(
      side_yaml(kDomain, 5.0, "master", "master", "remote", "attachment: operator, operator_grasp: 0.7", "tdpa"));
  Peer remote(kDomain, "remote", "master", hapticd_msg_TELEOP_REMOTE);
  std::atomic<bool> stopped{false};
  remote.set([&](hapticd_msg_TeleopPacket& p, double) {
    p.force[0] = -4.0;  // the remote's wall pushes back with 4 N
    p.energy_in = 1000.0;
    p.stopped = stopped.load();
  });
  server.start();
  ASSERT_TRUE(remote.wait_matched(20s));
  remote.start();
  // What the master renders (its published state's environment wrench: the link's force), as a client sees it.
  client::Client watcher({"watcher", kDomain});
  ASSERT_TRUE(watcher.wait_for_state("master", 20s).has_value());
  const auto rendered = [&] {
    const auto s = watcher.latest_state("master");
    return s ? s->environment_wrench.force : Eigen::Vector3d::Zero().eval();
  };
  // The operator holds still: the link's force is what the master displays (its passivity controller lets it
  // through: the remote reported enough energy, and the hand hardly moves).
  EXPECT_TRUE(wait_until([&] { return std::abs(rendered().x() + 4.0) < 0.5; }, 5000ms)) << rendered().transpose();
  // The remote falls silent: the force fades to nothing, without a fault.
  remote.stop();
  EXPECT_TRUE(wait_until([&] { return rendered().norm() < 0.05; }, 2000ms)) << rendered().transpose();
  EXPECT_EQ(server.device().status().fault(), DeviceFault::none);
  const TeleopLink& link = *server.bridge().teleop_link();
  EXPECT_EQ(link.losses(), 1u);
  EXPECT_EQ(link.stops(), 0u);
  // It comes back: the force returns.
  remote.start();
  EXPECT_TRUE(wait_until([&] { return std::abs(rendered().x() + 4.0) < 0.5; }, 3000ms)) << rendered().transpose();
  // The remote is stopped (its E-stop): the master stops too.
  stopped = true;
  EXPECT_TRUE(wait_until([&] { return server.device().status().fault() == DeviceFault::emergency_stop; }, 2000ms));
  EXPECT_EQ(link.stops(), 1u);
  remote.stop();
  server.join();  // the session's duration: a stopped device with a hand on it may take long to come to rest
}

// Hardening round 4, items 2 and 3: a third participant posing as the master (the right names and role, 1e9 J
// claimed) while the real master holds still, a forged serial of 2^64-1, and the master's server restarting. Before:
// the impostor drove the remote 39.4 mm through its wall at 40 N; one forged serial, or a restarted master (serials
// from 1 again), left the remote deaf to the master for good without a word.
TEST(TeleopLink, TheRemoteTakesOnlyItsBoundMastersPacketsAndTakesARestartedMasterBack) {
  constexpr int kDomain = 158;
  Server server(side_yaml(kDomain, 14.0, "remote", "remote", "master",
                          "attachment: none, wall_normal: [1.0, 0.0, 0.0], wall_offset_m: 0.03", "tdpa"));
  auto master = std::make_unique<Peer>(kDomain, "master", "remote", hapticd_msg_TELEOP_MASTER);
  master->set([](hapticd_msg_TeleopPacket& p, double) { p.energy_in = 0.0; });  // holds still
  server.start();
  ASSERT_TRUE(master->wait_matched(20s));
  master->start();
  const TeleopLink& link = *server.bridge().teleop_link();
  ASSERT_TRUE(wait_until([&] { return link.packets_taken() > 200; }, 5000ms));
  EXPECT_EQ(link.bindings(), 1u);

  // The impostor: 40 mm ahead along x (10 mm past the wall), at speed, claiming 1e9 J.
  Peer impostor(kDomain, "master", "remote", hapticd_msg_TELEOP_MASTER);
  impostor.set([](hapticd_msg_TeleopPacket& p, double t) {
    p.position[0] = std::min(0.04, 0.2 * t);
    p.velocity[0] = t < 0.2 ? 0.2 : 0.0;
    p.energy_in = 1e9;
  });
  impostor.count_from(1'000'000);  // ahead of the real master's serials
  ASSERT_TRUE(impostor.wait_matched(20s));
  impostor.start();
  std::this_thread::sleep_for(1500ms);
  impostor.forge_serial(~std::uint64_t{0});  // and a serial of 2^64-1 from the impostor too
  std::this_thread::sleep_for(500ms);
  impostor.stop();
  const hapticd_msg_TeleopPacket held = master->newest();
  EXPECT_LT(std::abs(held.position[0]), 0.002) << "the remote followed the impostor to " << held.position[0];
  EXPECT_GT(link.impostor_packets(), 500u);
  EXPECT_EQ(server.device().status().fault(), DeviceFault::none);

  // A forged serial of 2^64-1 from the bound master itself: older than its count by serial arithmetic, ignored;
  // the master's own packets go on being taken.
  master->forge_serial(~std::uint64_t{0});
  master->set([](hapticd_msg_TeleopPacket& p, double) {
    p.position[0] = 0.01;
    p.energy_in = 0.0;
  });
  EXPECT_TRUE(wait_until([&] { return master->newest().position[0] > 0.007; }, 3000ms))
      << "the remote no longer follows its master after a forged serial: " << master->newest().position[0];

  // The master's server restarts: the old participant goes, the remote stops when the link falls silent, a new one
  // (serials from 1) comes; the link re-binds to it and, once the person recovers the remote, the remote follows.
  master.reset();
  EXPECT_TRUE(wait_until([&] { return server.device().status().fault() == DeviceFault::emergency_stop; }, 3000ms));
  Peer restarted(kDomain, "master", "remote", hapticd_msg_TELEOP_MASTER);
  std::atomic<double> target{0.0};
  restarted.set([&](hapticd_msg_TeleopPacket& p, double) {
    p.position[0] = target.load();
    p.energy_in = 0.0;
  });
  ASSERT_TRUE(restarted.wait_matched(20s));
  restarted.start();
  EXPECT_TRUE(wait_until([&] { return link.bindings() == 2u; }, 3000ms)) << link.bindings();
  client::Client person({"person-at-the-remote", kDomain});
  ASSERT_TRUE(person.wait_for_device("remote", 20s).has_value());
  std::this_thread::sleep_for(300ms);
  const auto recovered = person.recover("remote", 5s);
  EXPECT_TRUE(recovered.accepted) << recovered.message;
  std::this_thread::sleep_for(500ms);
  const double before = restarted.newest().position[0];
  target = 0.02;  // the new master moves 2 cm: the remote follows (re-anchored where it was)
  EXPECT_TRUE(wait_until([&] { return restarted.newest().position[0] - before > 0.015; }, 4000ms))
      << "the remote moved " << restarted.newest().position[0] - before << " m after the master's restart";
  restarted.stop();
  server.join();
}

// Item 2, the master's side: a participant posing as the remote pushes with 40 N and claims 1e9 J (before: it
// pushed the master 160.6 mm and did 2.48 J of work on the operator's hand; the report said -0.0000 J); and the
// bound remote's own claim of 1e9 J at rest is credited only as far as its force and motion could carry it.
TEST(TeleopLink, TheMasterIgnoresAnImpostorAndCreditsOnlyEnergyTheLinkCouldCarry) {
  constexpr int kDomain = 159;
  Server server(
      side_yaml(kDomain, 6.0, "master", "master", "remote", "attachment: operator, operator_grasp: 0.7", "tdpa"));
  Peer remote(kDomain, "remote", "master", hapticd_msg_TELEOP_REMOTE);
  remote.set([](hapticd_msg_TeleopPacket& p, double) { p.energy_in = 1e9; });  // no force, no motion
  server.start();
  ASSERT_TRUE(remote.wait_matched(20s));
  remote.start();
  client::Client watcher({"watcher", kDomain});
  ASSERT_TRUE(watcher.wait_for_state("master", 20s).has_value());
  const TeleopLink& link = *server.bridge().teleop_link();
  ASSERT_TRUE(wait_until([&] { return link.packets_taken() > 200; }, 5000ms));
  const Eigen::Vector3d start = watcher.latest_state("master")->pose.position;
  Peer impostor(kDomain, "remote", "master", hapticd_msg_TELEOP_REMOTE);
  impostor.set([](hapticd_msg_TeleopPacket& p, double) {
    p.force[1] = 40.0;
    p.energy_in = 1e9;
  });
  impostor.count_from(1'000'000);  // ahead of the real remote's serials
  ASSERT_TRUE(impostor.wait_matched(20s));
  impostor.start();
  double largest = 0.0, moved = 0.0;
  for (int i = 0; i < 150; ++i) {
    std::this_thread::sleep_for(10ms);
    const auto s = watcher.latest_state("master");
    largest = std::max(largest, s->environment_wrench.force.norm());
    moved = std::max(moved, (s->pose.position - start).norm());
  }
  impostor.stop();
  EXPECT_LT(largest, 0.5) << "the master rendered the impostor's force";
  EXPECT_LT(moved, 0.005) << "the impostor moved the master's handle";
  EXPECT_GT(link.impostor_packets(), 500u);
  const TeleopLink::Energy e = link.energy();
  EXPECT_GT(e.peer_claimed, 1e8);
  EXPECT_LT(e.peer_credited, 0.01) << "a claim the link's force and motion could not carry was credited";
  remote.stop();
  server.join();
}

}  // namespace
}  // namespace hapticd::server
