// Device groups over DDS (docs/multi-device.md, "Groups over DDS"): the group description, a group state holding
// every device's state of one cycle, group claim (all or none, also in a race), group E-stop and recovery (and
// "*": every device), and lockstep runs with two engines - one per arm - that repeat bit for bit.
// Each test has a DDS domain of its own on the loopback interface.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "app/served_session.hpp"
#include "dds_server_rig.hpp"
#include "hapticd/client/client.hpp"
#include "support/test_session.hpp"

namespace hapticd::server::e2e {
namespace {

using namespace std::chrono_literals;

// A ViSHaRD3 in admittance display with the virtual coupling, at x_m along the world's x axis, its simulated
// operator pushing with `force_n`. Its safe mode holds gravity 0.2 s (not 10 s): the stopped server ends soon.
std::string arm(const std::string& name, double x_m, const std::string& force_n) {
  return test::sim_vishard3_device_yaml(name, "step", force_n) + R"(        wrench_force_start_s: 0.1
    base_pose: {xyz: [)" +
         std::to_string(x_m) + ", 0, 0]}\n" + coupling_chain_yaml() + "    safety: {safe_hold_s: 0.2, " +
         kRealtimeWatchdogs + "}\n";
}

// Two arms in the group "hands" and a third device outside it.
std::string hands_session(int domain, const std::string& clock, double duration_s, const std::string& devices = "") {
  return "server: {clock: " + clock +
         ", seed: 5, realtime_priority: 0, lock_memory: false, duration_s: " + std::to_string(duration_s) +
         "}\ndds: {domain_id: " + std::to_string(domain) +
         ", lockstep_start_wait_s: 20, lockstep_wait_s: 2}\ndevices:\n" +
         (devices.empty() ? arm("left", 0.0, "[0.0, 2.0, 0.0]") + arm("right", 2.0, "[0.0, -2.0, 0.0]") +
                                arm("third", 4.0, "[0.0, 0.0, 0.0]")
                          : devices) +
         "groups:\n  - name: hands\n    devices: [left, right]\n    min_distance_m: 0.02\n";
}

// What the loop did, cycle by cycle, for every device (on the loop thread).
class Trajectories final : public CycleListener {
 public:
  Trajectories(CycleListener* next, std::vector<DeviceSession*> devices) : next_(next), devices_(std::move(devices)) {
    for (auto& p : positions_) p.reserve(8000);
  }
  void after_cycle(std::uint64_t index, bool lockstep) noexcept override {
    for (std::size_t d = 0; d < devices_.size() && d < positions_.size(); ++d) {
      positions_[d].push_back(devices_[d]->chain_state().handle_pose.position);
    }
    next_->after_cycle(index, lockstep);
  }
  std::array<std::vector<Eigen::Vector3d>, 3> positions_;

 private:
  CycleListener* next_;
  std::vector<DeviceSession*> devices_;
};

// The session served as hapticd serves it, with every device's trajectory recorded.
class GroupServer {
 public:
  explicit GroupServer(const std::string& yaml) : session_(test::build_test_session(yaml)) {
    served_ = std::make_unique<ServedSession>(session_.impl().config, session_.impl().device_pointers(),
                                              session_.impl().stage_pointers(), ServeOptions{{}, false, nullptr});
    trajectories_ = std::make_unique<Trajectories>(served_->cycle_listener(), session_.impl().device_pointers());
    served_->set_cycle_listener(trajectories_.get());
  }
  ~GroupServer() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
  }
  void start() {
    thread_ = std::thread([this] { result_ = served_->run(stop_); });
  }
  void finish() {
    if (thread_.joinable()) thread_.join();
  }
  void stop() { stop_.store(true); }
  DdsBridge& bridge() { return *served_->bridge(); }
  DeviceSession& device(std::size_t i) { return *session_.impl().devices[i]; }
  const Trajectories& trajectories() const { return *trajectories_; }

 private:
  Session session_;
  std::unique_ptr<ServedSession> served_;
  std::unique_ptr<Trajectories> trajectories_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  ExecutorResult result_;
};

TEST(DdsGroups, TheGroupIsDescribedAndItsStateHoldsEveryDeviceFromOneCycle) {
  GroupServer server(hands_session(81, "realtime", 60.0));
  server.start();
  Client client({"observer", 81, {}, 0.05});
  const auto described = client.wait_for_group("hands", 10s);
  ASSERT_TRUE(described.has_value());
  EXPECT_EQ(described->version, hapticd_msg_VERSION);
  ASSERT_EQ(described->device_count, 2);
  EXPECT_EQ(client::name_of(described->devices[0]), "left");
  EXPECT_EQ(client::name_of(described->devices[1]), "right");
  EXPECT_EQ(described->min_distance_m, 0.02);
  // In real time, where a device's own state may be a cycle ahead of another's, every group state is of one
  // cycle, and its states are the devices' own states of that cycle.
  std::mutex m;
  std::vector<std::unique_ptr<hapticd_msg_GroupState>> groups;
  std::map<std::pair<std::string, std::uint64_t>, hapticd_msg_DeviceState> states;  // (device, cycle)
  client.on_state([&](const hapticd_msg_DeviceState& s) {
    std::lock_guard lock(m);
    if (states.size() < 20000) states[{std::string(client::name_of(s.device)), s.cycle}] = s;
  });
  client.on_group_state([&](const hapticd_msg_GroupState& g) {
    std::lock_guard lock(m);
    if (groups.size() < 2000) groups.push_back(std::make_unique<hapticd_msg_GroupState>(g));
  });
  for (int i = 0; i < 400; ++i) {  // at most 4 s
    {
      std::lock_guard lock(m);
      if (groups.size() >= 1000) break;
    }
    std::this_thread::sleep_for(10ms);
  }
  client.on_state({});
  client.on_group_state({});
  server.stop();
  server.finish();
  std::lock_guard lock(m);
  ASSERT_GE(groups.size(), 200u);
  std::size_t matched = 0;
  for (const auto& g : groups) {
    ASSERT_EQ(g->device_count, 2);
    EXPECT_EQ(client::name_of(g->states[0].device), "left");
    EXPECT_EQ(client::name_of(g->states[1].device), "right");
    EXPECT_GT(g->clearance_m, 1.0);  // measured: the arms stand 2 m apart
    for (int k = 0; k < 2; ++k) {
      ASSERT_EQ(g->states[k].cycle, g->cycle) << "a group state mixes cycles";
      const auto own = states.find({std::string(client::name_of(g->states[k].device)), g->cycle});
      if (own == states.end()) continue;  // (best effort: the device's own state of that cycle may be lost)
      ++matched;
      EXPECT_EQ(std::memcmp(&own->second.pose, &g->states[k].pose, sizeof own->second.pose), 0);
      EXPECT_EQ(own->second.serial, g->states[k].serial);
    }
  }
  EXPECT_GT(matched, groups.size());  // most are matched, for both devices
}

TEST(DdsGroups, AGroupClaimTakesEveryDeviceOrNoneEvenInARace) {
  GroupServer server(hands_session(82, "realtime", 120.0));
  server.start();
  Client a({"engine-a", 82, {}, 0.05}), b({"engine-b", 82, {}, 0.05}), single({"engine-c", 82, {}, 0.05});
  for (Client* c : {&a, &b, &single}) ASSERT_TRUE(c->wait_for_group("hands", 10s).has_value());
  ASSERT_TRUE(single.wait_for_device("right", 10s).has_value());
  const auto owner = [&](std::size_t i) { return server.bridge().owner(i); };
  int group_wins = 0, single_wins = 0;
  for (int round = 0; round < 6; ++round) {
    // Three claims at once: two for the group, one for the group's right arm alone.
    client::Reply ra, rb, rc;
    std::thread ta([&] { ra = a.claim_group("hands", 5s); });
    std::thread tb([&] { rb = b.claim_group("hands", 5s); });
    std::thread tc([&] { rc = single.claim("right", 5s); });
    ta.join();
    tb.join();
    tc.join();
    ASSERT_TRUE(ra.answered && rb.answered && rc.answered);
    const int accepted = int(ra.accepted) + int(rb.accepted) + int(rc.accepted);
    EXPECT_EQ(accepted, 1) << ra.message << " / " << rb.message << " / " << rc.message;
    if (rc.accepted) {
      ++single_wins;  // neither group claim took the left arm
      EXPECT_EQ(owner(0), "");
      EXPECT_EQ(owner(1), "engine-c");
      EXPECT_NE(ra.message.find("none claimed"), std::string::npos) << ra.message;
    } else {
      ++group_wins;  // one engine owns both arms
      const std::string winner = ra.accepted ? "engine-a" : "engine-b";
      EXPECT_EQ(owner(0), winner);
      EXPECT_EQ(owner(1), winner);
      const client::Reply& loser = ra.accepted ? rb : ra;
      EXPECT_NE(loser.message.find("none claimed"), std::string::npos) << loser.message;
    }
    EXPECT_EQ(owner(2), "");  // the device outside the group is never claimed by a group claim
    for (Client* c : {&a, &b}) (void)c->release_group("hands", 5s);
    (void)single.release("right", 5s);
    ASSERT_EQ(owner(0), "");
    ASSERT_EQ(owner(1), "");
  }
  EXPECT_EQ(group_wins + single_wins, 6);
  // Requests must name the right kind of target.
  EXPECT_FALSE(a.claim_group("left", 5s).accepted);
  EXPECT_FALSE(a.claim("hands", 5s).accepted);
  EXPECT_FALSE(a.claim_group("*", 5s).accepted);
}

TEST(DdsGroups, AGroupEStopStopsTheGroupAndOnlyItAndARecoveryIsAllOrNone) {
  GroupServer server(hands_session(83, "realtime", 120.0));
  server.start();
  Client owner({"owner", 83, {}, 0.05}), other({"other", 83, {}, 0.05});
  ASSERT_TRUE(owner.wait_for_group("hands", 10s).has_value());
  ASSERT_TRUE(other.wait_for_group("hands", 10s).has_value());
  ASSERT_TRUE(owner.wait_for_state("third", 10s).has_value());
  ASSERT_TRUE(owner.claim_group("hands", 5s).accepted);
  const client::Reply stop = other.emergency_stop_group("hands", 5s);  // anyone may stop
  EXPECT_TRUE(stop.accepted) << stop.message;
  const auto mode_of = [&](const std::string& device) {
    for (int i = 0; i < 300; ++i) {
      const auto s = owner.latest_state(device);
      if (s && s->mode == hapticd_msg_MODE_SAFE) return s->mode;
      std::this_thread::sleep_for(10ms);
    }
    return owner.latest_state(device)->mode;
  };
  EXPECT_EQ(mode_of("left"), hapticd_msg_MODE_SAFE);
  EXPECT_EQ(mode_of("right"), hapticd_msg_MODE_SAFE);
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(owner.latest_state("third")->mode, hapticd_msg_MODE_RUNNING);
  EXPECT_EQ(server.device(2).fault(), DeviceFault::none);
  // Recovery is the owner's: another client's group recovery recovers none.
  const client::Reply refused = other.recover_group("hands", 5s);
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(refused.message.find("none recovered"), std::string::npos) << refused.message;
  std::this_thread::sleep_for(1300ms);  // both at zero torque: damping 0.5 s, gravity held 0.2 s, released 0.5 s
  EXPECT_NE(server.device(0).fault(), DeviceFault::none);
  const client::Reply recovered = owner.recover_group("hands", 5s);
  EXPECT_TRUE(recovered.accepted) << recovered.message;
  for (int i = 0;
       i < 300 && (server.device(0).fault() != DeviceFault::none || server.device(1).fault() != DeviceFault::none); ++i)
    std::this_thread::sleep_for(10ms);
  EXPECT_EQ(server.device(0).fault(), DeviceFault::none);
  EXPECT_EQ(server.device(1).fault(), DeviceFault::none);
  // "*": every device of the server, the one outside the group too.
  EXPECT_TRUE(other.emergency_stop_group("*", 5s).accepted);
  for (int i = 0; i < 300 && server.device(2).fault() == DeviceFault::none; ++i) std::this_thread::sleep_for(10ms);
  for (std::size_t d = 0; d < 3; ++d) EXPECT_EQ(server.device(d).fault(), DeviceFault::emergency_stop) << d;
  for (int i = 0; i < 300 && !server.device(2).at_rest(); ++i) std::this_thread::sleep_for(10ms);
}

// One engine per arm, each answering its arm's every state with the proxy of a wall 3 cm ahead of the handle's
// start along x, 1 mm behind the virtual body (through the 3000 N/m coupling a 3 N pull from its first answer on:
// an engine that started late would show in the trajectory).
struct WallEngine {
  WallEngine(int domain, const std::string& id, std::string device_name)
      : client({id, domain, {}, 0.05}), device(std::move(device_name)) {}
  ~WallEngine() { client.on_state({}); }
  bool connect() {
    const auto first = client.wait_for_state(device, 20s);
    if (!first) return false;
    wall = client::pose_of(first->pose).position.x() + 0.03;
    if (!client.claim(device, 10s).accepted) return false;
    client.on_state([this](const hapticd_msg_DeviceState& s) {
      if (client::name_of(s.device) != device) return;
      Pose proxy = client::pose_of(s.target_pose);
      proxy.position.x() = std::min(proxy.position.x(), wall) - 0.001;  // and a 3 N pull from the first answer
      client.send_coupling(device, proxy, Twist{}, s.serial);
    });
    return true;
  }
  Client client;
  std::string device;
  double wall = 0.0;
};

// Two arms pushed along +x into walls their own engines render, in lockstep.
std::array<std::vector<Eigen::Vector3d>, 3> two_engine_run(int domain) {
  const std::string arms = arm("left", 0.0, "[6.0, 0.0, 0.0]") + arm("right", 2.0, "[6.0, 0.0, 0.0]");
  GroupServer server(hands_session(domain, "lockstep", 0.8, arms));
  WallEngine left(domain, "left-engine", "left"), right(domain, "right-engine", "right");
  server.start();
  EXPECT_TRUE(left.connect());
  std::this_thread::sleep_for(100ms);  // the second engine comes later: the first cycle waits for it too
  EXPECT_TRUE(right.connect());
  server.finish();
  EXPECT_EQ(server.bridge().lockstep_timeouts(), 0u);
  return server.trajectories().positions_;
}

TEST(DdsGroups, TwoArmLockstepRunsWithTwoEnginesAreBitIdentical) {
  const auto first = two_engine_run(84);
  const auto second = two_engine_run(84);
  for (std::size_t d = 0; d < 2; ++d) {
    ASSERT_GT(first[d].size(), 1700u);
    ASSERT_EQ(first[d].size(), second[d].size());
    std::size_t differ = 0;
    for (std::size_t k = 0; k < first[d].size(); ++k) differ += first[d][k] != second[d][k] ? 1 : 0;
    EXPECT_EQ(differ, 0u) << "device " << d;
  }
  // The engines acted: each arm went to its wall 3 cm ahead and was held there (6 N against 30 N s/m would carry
  // it about 14 cm).
  for (std::size_t d = 0; d < 2; ++d) {
    const double travel = first[d].back().x() - first[d].front().x();
    EXPECT_GT(travel, 0.02) << "device " << d;
    EXPECT_LT(travel, 0.05) << "device " << d;
  }
}

}  // namespace
}  // namespace hapticd::server::e2e
