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

#include "../../clients/engines/bimanual.hpp"
#include "app/served_session.hpp"
#include "dds_server_rig.hpp"
#include "hapticd/client/client.hpp"
#include "hapticd/client/engine.hpp"
#include "hapticd_msg.h"
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
  Doors& bridge() { return *served_->doors(); }  // the gate and its doors
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
  Client client({"observer", 81});
  const auto described = client.wait_for_group("hands", 10s);
  ASSERT_TRUE(described.has_value());
  EXPECT_EQ(described->version, hapticd_msg_VERSION);
  ASSERT_EQ(described->devices.size(), 2u);
  EXPECT_EQ(described->devices[0], "left");
  EXPECT_EQ(described->devices[1], "right");
  EXPECT_EQ(described->min_distance_m, 0.02);
  // In real time, where a device's own state may be a cycle ahead of another's, every group state is of one
  // cycle, and its states are the devices' own states of that cycle.
  std::mutex m;
  std::vector<std::unique_ptr<client::GroupState>> groups;
  std::map<std::pair<std::string, std::uint64_t>, client::DeviceState> states;  // (device, cycle)
  client.on_state([&](const client::DeviceState& s) {
    std::lock_guard lock(m);
    if (states.size() < 20000) states[{s.device.str(), s.cycle}] = s;
  });
  client.on_group_state([&](const client::GroupState& g) {
    std::lock_guard lock(m);
    if (groups.size() < 2000) groups.push_back(std::make_unique<client::GroupState>(g));
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
    EXPECT_EQ(g->states[0].device, "left");
    EXPECT_EQ(g->states[1].device, "right");
    EXPECT_GT(g->clearance_m, 1.0);  // measured: the arms stand 2 m apart
    for (int k = 0; k < 2; ++k) {
      ASSERT_EQ(g->states[k].cycle, g->cycle) << "a group state mixes cycles";
      const auto own = states.find({g->states[k].device.str(), g->cycle});
      if (own == states.end()) continue;  // (best effort: the device's own state of that cycle may be lost)
      ++matched;
      EXPECT_EQ(own->second.pose.position, g->states[k].pose.position);  // bit for bit
      EXPECT_EQ(own->second.pose.orientation.coeffs(), g->states[k].pose.orientation.coeffs());
      EXPECT_EQ(own->second.serial, g->states[k].serial);
    }
  }
  EXPECT_GT(matched, groups.size());  // most are matched, for both devices
}

TEST(DdsGroups, AGroupClaimTakesEveryDeviceOrNoneEvenInARace) {
  GroupServer server(hands_session(82, "realtime", 120.0));
  server.start();
  Client a({"engine-a", 82}), b({"engine-b", 82}), single({"engine-c", 82});
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

TEST(DdsGroups, AGroupClaimAfterADeviceClaimUnderAnotherIdOfTheSameParticipantIsRefusedNotAnAbort) {
  // The attack (hardening round 3, item 1): one participant claims `left` as client A, then the group holding it
  // as client B. The group claim took `left` for free (the same participant) while the gate wanted the same
  // client id too: an invariant check aborted the server, both arms lost power without their safe ramp.
  GroupServer server(hands_session(140, "realtime", 60.0));
  server.start();
  RawRequester attacker(140);
  Client observer({"observer", 140});
  ASSERT_TRUE(observer.wait_for_group("hands", 10s).has_value());
  const auto a = attacker.request("left", hapticd_msg_REQUEST_CLAIM, "client-a");
  ASSERT_TRUE(a.answered && a.accepted) << a.message;
  const auto b = attacker.request("hands", hapticd_msg_REQUEST_GROUP_CLAIM, "client-b");
  ASSERT_TRUE(b.answered) << "the server did not answer (aborted?)";
  EXPECT_FALSE(b.accepted) << b.message;
  EXPECT_NE(b.message.find("none claimed: left by 'client-a'"), std::string::npos) << b.message;
  EXPECT_EQ(server.bridge().owner(0), "client-a");
  EXPECT_EQ(server.bridge().owner(1), "");  // all or none: right was not taken either
  // Under the id it claimed with, the same participant may take the whole group.
  const auto again = attacker.request("hands", hapticd_msg_REQUEST_GROUP_CLAIM, "client-a");
  EXPECT_TRUE(again.accepted) << again.message;
  EXPECT_EQ(server.bridge().owner(1), "client-a");
  // The devices ran on throughout.
  EXPECT_EQ(server.device(0).status().fault(), DeviceFault::none);
  EXPECT_EQ(server.device(1).status().fault(), DeviceFault::none);
}

TEST(DdsGroups, AStopLatchesUntilItsStopperReleasesItForDeviceAndGroupRequestsAlike) {
  // The attack (hardening round 3, item 5): an operator stops a device, any other participant recovered it
  // (a device recovery on the free device, or "*"). A stop now holds until whoever made it releases it.
  GroupServer server(hands_session(141, "realtime", 120.0));
  server.start();
  RawRequester operator_console(141), other(141);
  Client watcher({"watcher", 141});
  ASSERT_TRUE(watcher.wait_for_group("hands", 10s).has_value());
  ASSERT_TRUE(watcher.wait_for_state("third", 10s).has_value());
  const auto stopped = operator_console.request("third", hapticd_msg_REQUEST_ESTOP, "operator");
  ASSERT_TRUE(stopped.accepted) << stopped.message;
  for (int i = 0; i < 300 && server.device(2).status().fault() == DeviceFault::none; ++i)
    std::this_thread::sleep_for(10ms);
  ASSERT_EQ(server.device(2).status().fault(), DeviceFault::emergency_stop);
  std::this_thread::sleep_for(1300ms);  // the safe mode at zero torque: a recovery could be carried out now
  // Another participant, under any id (the operator's too while the operator is there), recovers nothing.
  for (const char* id : {"engine", "operator"}) {
    const auto refused = other.request("third", hapticd_msg_REQUEST_RECOVER, id);
    ASSERT_TRUE(refused.answered);
    EXPECT_FALSE(refused.accepted) << id;
    EXPECT_NE(refused.message.find("stopped by 'operator'"), std::string::npos) << refused.message;
  }
  const auto every = other.request("*", hapticd_msg_REQUEST_GROUP_RECOVER, "engine");
  EXPECT_FALSE(every.accepted) << every.message;
  EXPECT_NE(every.message.find("none recovered"), std::string::npos) << every.message;
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(server.device(2).status().fault(), DeviceFault::emergency_stop)
      << "another participant undid the operator's stop";
  EXPECT_EQ(server.device(2).status().recoveries(), 0u);
  // Two stoppers: each releases its own stop (lockout-tagout); the device recovers once none holds it.
  ASSERT_TRUE(other.request("third", hapticd_msg_REQUEST_ESTOP, "supervisor").accepted);
  const auto first = operator_console.request("third", hapticd_msg_REQUEST_RECOVER, "operator");
  EXPECT_FALSE(first.accepted);
  EXPECT_NE(first.message.find("its stop released, stopped by 'supervisor'"), std::string::npos) << first.message;
  std::this_thread::sleep_for(1300ms);
  const auto last = other.request("third", hapticd_msg_REQUEST_RECOVER, "supervisor");
  EXPECT_TRUE(last.accepted) << last.message;
  for (int i = 0; i < 1000 && server.device(2).status().fault() != DeviceFault::none; ++i)
    std::this_thread::sleep_for(10ms);
  EXPECT_EQ(server.device(2).status().fault(), DeviceFault::none);
  // A group stop through "*" latches every device under its stopper: a group recovery by another is refused,
  // the stopper's is all or none.
  ASSERT_TRUE(operator_console.request("*", hapticd_msg_REQUEST_GROUP_ESTOP, "operator").accepted);
  for (int i = 0; i < 300 && server.device(0).status().fault() == DeviceFault::none; ++i)
    std::this_thread::sleep_for(10ms);
  std::this_thread::sleep_for(1300ms);
  EXPECT_FALSE(other.request("hands", hapticd_msg_REQUEST_GROUP_RECOVER, "engine").accepted);
  EXPECT_FALSE(other.request("left", hapticd_msg_REQUEST_RECOVER, "engine").accepted);
  const auto group = operator_console.request("hands", hapticd_msg_REQUEST_GROUP_RECOVER, "operator");
  EXPECT_TRUE(group.accepted) << group.message;
  const auto rest = operator_console.request("third", hapticd_msg_REQUEST_RECOVER, "operator");
  EXPECT_TRUE(rest.accepted) << rest.message;
  for (int i = 0; i < 1000 && (server.device(0).status().fault() != DeviceFault::none ||
                               server.device(2).status().fault() != DeviceFault::none);
       ++i)
    std::this_thread::sleep_for(10ms);
  EXPECT_EQ(server.device(0).status().fault(), DeviceFault::none);
  EXPECT_EQ(server.device(1).status().fault(), DeviceFault::none);
  EXPECT_EQ(server.device(2).status().fault(), DeviceFault::none);
}

TEST(DdsGroups, AGroupEStopStopsTheGroupAndOnlyItAndARecoveryIsAllOrNone) {
  GroupServer server(hands_session(83, "realtime", 120.0));
  server.start();
  Client owner({"owner", 83}), other({"other", 83});
  ASSERT_TRUE(owner.wait_for_group("hands", 10s).has_value());
  ASSERT_TRUE(other.wait_for_group("hands", 10s).has_value());
  ASSERT_TRUE(owner.wait_for_state("third", 10s).has_value());
  ASSERT_TRUE(owner.claim_group("hands", 5s).accepted);
  const client::Reply stop = other.emergency_stop_group("hands", 5s);  // anyone may stop
  EXPECT_TRUE(stop.accepted) << stop.message;
  const auto mode_of = [&](const std::string& device) {
    for (int i = 0; i < 300; ++i) {
      const auto s = owner.latest_state(device);
      if (s && s->mode == client::Mode::safe) return s->mode;
      std::this_thread::sleep_for(10ms);
    }
    return owner.latest_state(device)->mode;
  };
  EXPECT_EQ(mode_of("left"), client::Mode::safe);
  EXPECT_EQ(mode_of("right"), client::Mode::safe);
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(owner.latest_state("third")->mode, client::Mode::running);
  EXPECT_EQ(server.device(2).status().fault(), DeviceFault::none);
  // The stop holds until its stopper releases it: neither the owner nor a bystander recovers the group.
  Client bystander({"bystander", 83});
  for (Client* c : {&owner, &bystander}) {
    const client::Reply refused = c->recover_group("hands", 5s);
    EXPECT_FALSE(refused.accepted);
    EXPECT_NE(refused.message.find("none recovered"), std::string::npos) << refused.message;
    EXPECT_NE(refused.message.find("stopped by 'other'"), std::string::npos) << refused.message;
  }
  std::this_thread::sleep_for(1300ms);  // both at zero torque: damping 0.5 s, gravity held 0.2 s, released 0.5 s
  EXPECT_NE(server.device(0).status().fault(), DeviceFault::none);
  const client::Reply recovered = other.recover_group("hands", 5s);
  EXPECT_TRUE(recovered.accepted) << recovered.message;
  // At most 10 s: under ThreadSanitizer with other tests beside it, the bridge's threads can lag by seconds.
  for (int i = 0; i < 1000 && (server.device(0).status().fault() != DeviceFault::none ||
                               server.device(1).status().fault() != DeviceFault::none);
       ++i)
    std::this_thread::sleep_for(10ms);
  EXPECT_EQ(server.device(0).status().fault(), DeviceFault::none);
  EXPECT_EQ(server.device(1).status().fault(), DeviceFault::none);
  // "*": every device of the server, the one outside the group too.
  EXPECT_TRUE(other.emergency_stop_group("*", 5s).accepted);
  const auto all_stopped = [&] {  // (each at the next cycle its loop reads the request: not necessarily the same)
    for (std::size_t d = 0; d < 3; ++d)
      if (server.device(d).status().fault() == DeviceFault::none) return false;
    return true;
  };
  for (int i = 0; i < 300 && !all_stopped(); ++i) std::this_thread::sleep_for(10ms);
  for (std::size_t d = 0; d < 3; ++d) EXPECT_EQ(server.device(d).status().fault(), DeviceFault::emergency_stop) << d;
  for (int i = 0; i < 300 && !server.device(2).status().at_rest(); ++i) std::this_thread::sleep_for(10ms);
}

// One engine per arm, each answering its arm's every state with the proxy of a wall 3 cm ahead of the handle's
// start along x, 1 mm behind the virtual body (through the 3000 N/m coupling a 3 N pull from its first answer on:
// an engine that started late would show in the trajectory).
struct WallEngine {
  WallEngine(int domain, const std::string& id, std::string device_name)
      : client({id, domain}), device(std::move(device_name)) {}
  ~WallEngine() { client.on_state({}); }
  bool connect() {
    const auto first = client.wait_for_state(device, 20s);
    if (!first) return false;
    wall = first->pose.position.x() + 0.03;
    if (!client.claim(device, 10s).accepted) return false;
    client.on_state([this](const client::DeviceState& s) {
      if (s.device != device) return;
      Pose proxy = s.target_pose;
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

// One engine for the whole group: it claims the group and answers each group state with one group command,
// a wall 3 cm ahead of each handle's start (and a 1 mm pull), as WallEngine does per device.
TEST(DdsGroups, AnEngineCouplesToAWholeGroupWithOneCommandPerCycle) {
  const std::string arms = arm("left", 0.0, "[6.0, 0.0, 0.0]") + arm("right", 2.0, "[6.0, 0.0, 0.0]");
  GroupServer server(hands_session(85, "lockstep", 0.8, arms));
  Client engine({"group-engine", 85});
  server.start();
  ASSERT_TRUE(engine.wait_for_group("hands", 20s).has_value());
  const auto first = engine.wait_for_group_state("hands", 20s);
  ASSERT_TRUE(first.has_value());
  const std::array<double, 2> wall = {first->states[0].pose.position.x() + 0.03,
                                      first->states[1].pose.position.x() + 0.03};
  ASSERT_TRUE(engine.claim_group("hands", 10s).accepted);
  std::atomic<std::uint64_t> sent{0};
  engine.on_group_state([&](const client::GroupState& g) {
    std::array<client::DeviceCommand, 2> commands;
    for (std::size_t k = 0; k < 2; ++k) {
      const client::DeviceState& s = g.states[k];
      Pose proxy = s.target_pose;
      proxy.position.x() = std::min(proxy.position.x(), wall[k]) - 0.001;
      commands[k] = {s.device, client::EngineCommand::coupling(proxy, Twist{}, s.serial)};
    }
    if (engine.send_group("hands", commands)) sent.fetch_add(1);
  });
  server.finish();
  engine.on_group_state({});
  EXPECT_EQ(server.bridge().lockstep_timeouts(), 0u);
  EXPECT_GT(sent.load(), 1500u);
  for (std::size_t d = 0; d < 2; ++d) {
    // Both devices took every group command's part for them ...
    EXPECT_GE(server.bridge().commands_accepted(d), sent.load() - 2) << d;
    EXPECT_EQ(server.bridge().commands_rejected(d), 0u) << d;
    // ... and were held at their walls.
    const auto& p = server.trajectories().positions_[d];
    const double travel = p.back().x() - p.front().x();
    EXPECT_GT(travel, 0.02) << d;
    EXPECT_LT(travel, 0.05) << d;
  }
  EXPECT_EQ(server.bridge().unknown_device_commands(), 0u);
}

// A ViSHaRD3 held by a simulated operator, with the virtual coupling, at `base`.
std::string held_arm(const std::string& name, const std::string& base) {
  return test::sim_vishard3_held_yaml(name, base) + coupling_chain_yaml();
}

// The example bimanual engine (clients/engines/bimanual.hpp) over DDS: the ViSHaRD3 pair's operators lift the
// engine's box 10 cm and turn it 30 degrees, as the shared_object group model's test does in-process.
TEST(DdsGroups, TheBimanualEngineLetsTwoOperatorsLiftAndTurnItsBox) {
  const std::string arms = held_arm("left", "{xyz: [0, 0, 0]}") +
                           held_arm("right", "{xyz: [0.45, 0.558, 0], rpy: [0, 0, 3.141592653589793]}");
  GroupServer server(hands_session(86, "lockstep", 4.5, arms));
  Client client({"bimanual-engine", 86});
  model::SharedBodySettings box;
  box.size_m = Eigen::Vector3d(0.32, 0.15, 0.10);
  examples::BimanualEngine box_engine(client, box);
  // Run as the shipped engine runs it: by the engine helper, on a thread of its own.
  client::Engine engine(client, {.name = "bimanual-engine", .group = "hands", .wait = 20s});
  server.start();
  ASSERT_TRUE(engine.connect());
  ASSERT_EQ(box_engine.prepare("hands", engine.devices(), 20s), "");
  const examples::BoxReport start = box_engine.start();
  client::EngineEnd ended;
  std::atomic<bool> done{false};
  std::thread runs([&] {
    ended = engine.run([&](auto s, auto c) { return box_engine.answer(s, c); });
    done.store(true);
  });
  struct Join {
    client::Engine& e;
    std::thread& t;
    ~Join() {
      e.stop();
      t.join();
    }
  } join{engine, runs};
  // The operators, driven by loop time: at 0.5 s both carry half the weight and aim 10 cm up over 1 s; at 2 s
  // both move along the chords of a 30 degree turn about the box's vertical axis, over 1 s.
  const auto loop_time = [&] {
    const auto g = client.latest_group_state("hands");
    return g ? static_cast<double>(g->loop_time_ns) * 1e-9 : 0.0;
  };
  while (loop_time() < 0.5) std::this_thread::sleep_for(1ms);
  for (const char* name : {"left", "right"}) {
    EXPECT_TRUE(client.operator_command(name, "push", {0.0, 0.0, 4.905, 1.0}).accepted);
    EXPECT_TRUE(client.operator_command(name, "move", {0.0, 0.0, 0.10, 1.0}).accepted);
  }
  while (loop_time() < 2.0) std::this_thread::sleep_for(1ms);
  const examples::BoxReport lifted = box_engine.report();
  const auto g = client.latest_group_state("hands");
  for (int k = 0; k < 2; ++k) {
    Eigen::Vector3d r = g->states[k].pose.position - lifted.position;
    r.z() = 0.0;
    const Eigen::Vector3d d =
        Eigen::AngleAxisd(30.0 * 3.14159265358979323846 / 180.0, Eigen::Vector3d::UnitZ()) * r - r;
    EXPECT_TRUE(client.operator_command(g->states[k].device, "move", {d.x(), d.y(), 0.0, 1.0}).accepted);
  }
  server.finish();
  const examples::BoxReport end = box_engine.report();
  // The helper saw the session end (its last states said so) and ended the run by itself.
  for (int i = 0; i < 100 && !done.load(); ++i) std::this_thread::sleep_for(50ms);
  ASSERT_TRUE(done.load()) << "the engine helper did not end with the session";
  EXPECT_EQ(ended.reason, client::EngineEndReason::session_ended) << ended.message;
  EXPECT_EQ(server.bridge().lockstep_timeouts(), 0u);
  EXPECT_GT(end.answered, 8000u);  // every group state of the 4.5 s (and the ramp)
  EXPECT_NEAR(lifted.position.z() - start.position.z(), 0.10, 0.02);
  EXPECT_EQ(lifted.table_force_n, 0.0);
  EXPECT_NEAR(end.position.z() - start.position.z(), 0.10, 0.02);
  EXPECT_NEAR(end.yaw_deg - start.yaw_deg, 30.0, 4.0);
  // Held still after a rigid turn: little squeeze left (0.7 N measured; the engine couples the box to the measured
  // handles, the server its proxies to the virtual bodies, which the handles follow within a fraction of a mm).
  EXPECT_LT(std::abs(end.internal_force_n), 1.5);
  EXPECT_EQ(server.device(0).status().fault(), DeviceFault::none);
  EXPECT_EQ(server.device(1).status().fault(), DeviceFault::none);
}

}  // namespace
}  // namespace hapticd::server::e2e
