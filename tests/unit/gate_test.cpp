// The gate without any transport (server/src/gate, docs/architecture.md "The gate and its doors"): doors made
// here stand for DDS and the engine socket - they vouch for their peers' presence and record what the gate hands
// them - around a lockstep session of the simulated ViSHaRD3. Claims, admission, stop latches, the end of a
// departed peer's claim and the fan-out of states and events are checked through the gate's own calls.
#include "gate/gate.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <mutex>
#include <set>
#include <thread>

#include "hapticd/dds/conversion.hpp"
#include "session/device_session.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

// A door whose peers are present while the test says so, recording what the gate hands it.
class FakeDoor final : public Door {
 public:
  explicit FakeDoor(DoorKind kind) : kind_(kind) {}
  [[nodiscard]] DoorKind kind() const noexcept override { return kind_; }
  [[nodiscard]] bool channel_open(const Sender& s) const override {
    std::lock_guard lock(mutex_);
    return s.peer.door == kind_ && gone_.count(s.peer.key[0]) == 0;
  }
  [[nodiscard]] bool alive(const PeerId& p) override { return channel_open(Sender{p, 0}); }
  void state(std::size_t device, const DeviceSnapshot&, const hapticd_msg_DeviceState& m) override {
    std::lock_guard lock(mutex_);
    states_.push_back({device, m.serial});
  }
  void event(const hapticd_msg_Event& e) override {
    std::lock_guard lock(mutex_);
    events_.push_back(std::string(dds::text_of(e.message)));
  }
  void leave(unsigned char peer) {
    std::lock_guard lock(mutex_);
    gone_.insert(peer);
  }
  std::size_t states() const {
    std::lock_guard lock(mutex_);
    return states_.size();
  }
  std::vector<std::string> events() const {
    std::lock_guard lock(mutex_);
    return events_;
  }

 private:
  DoorKind kind_;
  mutable std::mutex mutex_;
  std::set<unsigned char> gone_;
  std::vector<std::pair<std::size_t, std::uint64_t>> states_;
  std::vector<std::string> events_;
};

// The same key bytes under two doors: a DDS participant and a socket connection that must not be confused.
Sender dds_peer(unsigned char n, std::uint64_t writer = 0) {
  std::array<unsigned char, 16> guid{};
  guid[0] = n;
  return Sender{PeerId::dds_participant(guid), writer == 0 ? n * 100u : writer};
}
Sender socket_peer(unsigned char n) { return Sender{PeerId::socket(n), 0}; }

hapticd_msg_ControlRequest request(hapticd_msg_RequestKind kind, const char* client, std::uint64_t id) {
  hapticd_msg_ControlRequest r{};
  dds::set_text(r.device, "v3");
  dds::set_text(r.client, client);
  r.kind = kind;
  r.request_id = id;
  return r;
}

hapticd_msg_EngineCommand command(const char* engine, std::uint64_t serial) {
  hapticd_msg_EngineCommand c{};
  dds::set_text(c.device, "v3");
  dds::set_text(c.engine, engine);
  c.serial = serial;
  c.kind = hapticd_msg_COMMAND_COUPLING;
  c.command_pose.position[0] = -0.3;
  c.command_pose.position[1] = 1.6;
  c.command_pose.orientation[0] = 1.0;
  c.anchor.orientation[0] = 1.0;
  return c;
}

class GateTest : public ::testing::Test {
 protected:
  GateTest()
      : session_(test::build_test_session(test::sim_vishard3_session_head("v3", 5) +
                                          test::vishard3_admittance_chain_yaml())),
        gate_(GateSettings{}, 2000.0, {&test::device_of(session_)}) {
    gate_.add_door(dds_);
    gate_.add_door(socket_);
  }
  std::int64_t now() const { return dds::wall_clock_ns(); }

  Session session_;
  FakeDoor dds_{DoorKind::dds}, socket_{DoorKind::socket};
  Gate gate_;
};

TEST_F(GateTest, APeerIsItsDoorsAndOnlyTheClaimantIsHeard) {
  EXPECT_EQ(gate_.admit(command("engine", 1), socket_peer(1), now()).reason, dds::RejectReason::not_owner);
  const auto claimed = gate_.requests().answer(request(hapticd_msg_REQUEST_CLAIM, "engine", 1), socket_peer(1));
  ASSERT_TRUE(claimed.accepted) << claimed.message;
  EXPECT_TRUE(gate_.admit(command("engine", 1), socket_peer(1), now()).accepted);
  // The same key bytes and client id through another door are another peer: not the owner, and no claim.
  EXPECT_EQ(gate_.admit(command("engine", 2), dds_peer(1), now()).reason, dds::RejectReason::not_owner);
  EXPECT_FALSE(gate_.requests().answer(request(hapticd_msg_REQUEST_CLAIM, "engine", 2), dds_peer(1)).accepted);
  EXPECT_FALSE(gate_.requests().answer(request(hapticd_msg_REQUEST_RELEASE, "engine", 3), dds_peer(1)).accepted);
  EXPECT_EQ(gate_.owner(0), "engine");
  // Order per channel, freshness by the stamp the door passes.
  EXPECT_EQ(gate_.admit(command("engine", 1), socket_peer(1), now()).reason, dds::RejectReason::out_of_order);
  EXPECT_EQ(gate_.admit(command("engine", 5), socket_peer(1), now() - 1'000'000'000).reason, dds::RejectReason::stale);
  // A command for a device the server does not have: malformed, counted.
  hapticd_msg_EngineCommand elsewhere = command("engine", 6);
  dds::set_text(elsewhere.device, "v9");
  EXPECT_EQ(gate_.admit(elsewhere, socket_peer(1), now()).reason, dds::RejectReason::malformed);
  EXPECT_EQ(gate_.unknown_device_commands(), 1u);
  EXPECT_EQ(gate_.commands_accepted(0), 1u);
  EXPECT_EQ(gate_.commands_rejected(0), 4u);  // not the owner twice, out of order, stale
}

TEST_F(GateTest, AClaimEndsWhenItsDoorSaysThePeerLeftAndEveryDoorIsTold) {
  ASSERT_TRUE(gate_.requests().answer(request(hapticd_msg_REQUEST_CLAIM, "engine", 1), dds_peer(7)).accepted);
  gate_.requests().check_claims();
  EXPECT_EQ(gate_.owner(0), "engine");  // present: kept
  dds_.leave(7);
  gate_.requests().check_claims();
  EXPECT_EQ(gate_.owner(0), "");
  EXPECT_EQ(gate_.claims_ended(), 1u);
  for (const FakeDoor* door : {&dds_, &socket_}) {
    const std::vector<std::string> events = door->events();
    ASSERT_FALSE(events.empty());
    EXPECT_NE(events.back().find("left the domain"), std::string::npos) << events.back();
  }
  // Another door's peer may claim the free device now.
  EXPECT_TRUE(gate_.requests().answer(request(hapticd_msg_REQUEST_CLAIM, "web", 2), socket_peer(7)).accepted);
}

TEST_F(GateTest, AStopHoldsUntilItsStopperReleasesItWhateverDoorItCameThrough) {
  ASSERT_TRUE(gate_.requests().answer(request(hapticd_msg_REQUEST_ESTOP, "console", 1), socket_peer(3)).accepted);
  // Someone else, through DDS, under the same client id while the stopper is connected: refused.
  const auto refused = gate_.requests().answer(request(hapticd_msg_REQUEST_RECOVER, "console", 2), dds_peer(4));
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(std::string(dds::text_of(refused.message)).find("'console'"), std::string::npos);
  // Once the stopper's connection closed, a client under its id may release the stop (a one-shot console).
  socket_.leave(3);
  const auto released = gate_.requests().answer(request(hapticd_msg_REQUEST_RECOVER, "console", 3), dds_peer(4));
  EXPECT_EQ(std::string(dds::text_of(released.message)).find("stopped by"), std::string::npos)
      << dds::text_of(released.message);
}

TEST_F(GateTest, AParameterSetThroughOneDoorIsAnEventAtEveryDoor) {
  hapticd_msg_ControlRequest set = request(hapticd_msg_REQUEST_SET_PARAMETER, "console", 1);
  dds::set_text(set.subject, "virtual_model.damping_n_s_per_m");
  set.value_count = 3;
  set.values[0] = set.values[1] = set.values[2] = 45.0;
  const auto reply = gate_.requests().answer(set, socket_peer(2));
  ASSERT_TRUE(reply.accepted) << dds::text_of(reply.message);
  for (const FakeDoor* door : {&dds_, &socket_}) {
    const std::vector<std::string> events = door->events();
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events.back(), "virtual_model.damping_n_s_per_m = [45, 45, 45] (set by 'console')");
  }
}

TEST_F(GateTest, OthersSetAClaimedDevicesParametersOnlyWhenTheSessionSaysSoAndNeverItsSafety) {
  ASSERT_TRUE(gate_.requests().answer(request(hapticd_msg_REQUEST_CLAIM, "engine", 1), dds_peer(1)).accepted);
  hapticd_msg_ControlRequest set = request(hapticd_msg_REQUEST_SET_PARAMETER, "console", 2);
  dds::set_text(set.subject, "virtual_model.damping_n_s_per_m");
  set.value_count = 3;
  set.values[0] = set.values[1] = set.values[2] = 45.0;
  EXPECT_FALSE(gate_.requests().answer(set, socket_peer(2)).accepted);  // gate.tuning_by: owner (the default)
  GateSettings anyone;
  anyone.tuning_by_anyone = true;
  Gate tuned(anyone, 2000.0, {&test::device_of(session_)});
  FakeDoor door(DoorKind::dds);
  tuned.add_door(door);
  ASSERT_TRUE(tuned.requests().answer(request(hapticd_msg_REQUEST_CLAIM, "engine", 1), dds_peer(1)).accepted);
  const auto accepted = tuned.requests().answer(set, dds_peer(2));
  EXPECT_TRUE(accepted.accepted) << dds::text_of(accepted.message);
  ASSERT_FALSE(door.events().empty());
  EXPECT_EQ(door.events().back(), "virtual_model.damping_n_s_per_m = [45, 45, 45] (set by 'console')");
  hapticd_msg_ControlRequest safety = request(hapticd_msg_REQUEST_SET_PARAMETER, "console", 3);
  dds::set_text(safety.subject, "safety.passivity_control");
  safety.value_count = 1;
  EXPECT_FALSE(tuned.requests().answer(safety, dds_peer(2)).accepted);
}

TEST_F(GateTest, EachStateReachesEveryDoor) {
  DeviceSession& d = test::device_of(session_);
  gate_.start();
  d.activate();
  for (std::uint64_t k = 0; k < 20; ++k) {
    d.cycle(test::cycle_at(k), 1.0);
    gate_.after_cycle(k, false);
  }
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while ((dds_.states() == 0 || socket_.states() == 0) && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  gate_.stop();
  d.deactivate();
  EXPECT_GT(dds_.states(), 0u);
  EXPECT_EQ(dds_.states(), socket_.states());  // one message made, handed to both
}

}  // namespace
}  // namespace hapticd::server
