// Ownership over DDS, as an attacker on the same host tried it (issue 17, items 2 and 3): a claim is bound to
// the claimant's DDS participant, not to the client id it declares, and it ends when that participant is gone -
// a clean exit without a release, a kill before or after the first command, a freeze beyond the liveliness
// lease - within 1 s. Real time on loopback, each test on a domain of its own, bounded in time; the killed and
// frozen claimants are separate processes (hapticctl, the scene engine).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "e2e/dds_server_rig.hpp"
#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "support/child_process.hpp"
#include "support/test_paths.hpp"

extern char** environ;

namespace hapticd::server {
namespace {

using client::Client;
using e2e::SceneEngine;
using e2e::Server;
using e2e::session_yaml;
using test::Process;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The owner the device's newest state names, as a client sees it.
std::string owner_seen(Client& watcher) {
  const auto s = watcher.wait_for_state("v3", std::chrono::seconds(2),
                                        watcher.latest_state("v3") ? watcher.latest_state("v3")->serial : 0);
  return s ? s->owner.str() : "?";
}

// Waits (at most `limit` s) until the device's owner is `owner`; returns the time it took, or nullopt.
std::optional<double> wait_for_owner(Client& watcher, const std::string& owner, double limit) {
  const auto start = Clock::now();
  while (seconds_since(start) < limit) {
    if (owner_seen(watcher) == owner) return seconds_since(start);
  }
  return std::nullopt;
}

// A separate process, killed at the end of the test whatever happened.
std::string bin(const char* name) { return hapticd::test::bin_dir() + "/" + name; }

TEST(DdsOwnership, AnotherParticipantWritingUnderTheOwnersIdIsNotTheOwner) {
  // The attack: a second process writes commands under the owning engine's id with serials near 2^64 (60 N,
  // the handle dragged), and sends release, recover, set and switch under that id. Before, 4409 such commands
  // were accepted and the real engine's were all rejected "out of order" afterwards.
  Server server(session_yaml(71, 60.0, "constant", "[0.0, 0.0, 0.0]", "realtime"));
  SceneEngine owner(71, "engine");
  server.start();
  ASSERT_TRUE(owner.connect());
  const auto not_owner = [&] {
    return server.bridge().rejected_by_reason(0)[static_cast<std::size_t>(dds::RejectReason::not_owner)];
  };
  const auto accepted_before = server.bridge().commands_accepted(0);

  // The requests, from a client of its own that declares the owner's id.
  Client spoofer({"engine", 71});
  ASSERT_TRUE(spoofer.wait_for_state("v3", std::chrono::seconds(10)));
  for (const client::Reply& r :
       {spoofer.claim("v3"), spoofer.release("v3"), spoofer.recover("v3"), spoofer.switch_scheme("v3", "default"),
        spoofer.set_parameter("v3", "virtual_model.coupling_stiffness_n_per_m", {100.0})}) {
    EXPECT_TRUE(r.answered) << r.message;
    EXPECT_FALSE(r.accepted) << r.message;
  }

  // The commands, raw: a participant and writer of their own, the owner's id, serials from 2^64 - 10000.
  dds::Participant participant(dds::ParticipantOptions{71, {}, {}});
  dds::Writer<hapticd_msg_EngineCommand> writer(participant, dds::CommandTiming{0.05, 0.5});
  const auto state = spoofer.latest_state("v3");
  ASSERT_TRUE(state.has_value());
  std::uint64_t serial = ~std::uint64_t{0} - 10000;
  const auto flood_start = Clock::now();
  const std::uint64_t not_owner_before = not_owner();
  while (seconds_since(flood_start) < 1.5 && serial < ~std::uint64_t{0}) {
    hapticd_msg_EngineCommand c{};
    dds::set_text(c.device, "v3");
    dds::set_text(c.engine, "engine");
    c.serial = ++serial;
    c.state_serial = state->serial;
    c.kind = hapticd_msg_COMMAND_WRENCH;
    c.wrench[0] = 60.0;
    c.command_pose.orientation[0] = 1.0;
    c.anchor.orientation[0] = 1.0;
    (void)writer.write(c);
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  const std::uint64_t spoofed = not_owner() - not_owner_before;
  // The real engine goes on being heard: 100 more of its commands accepted (waited for, at most 10 s: how soon
  // depends on the machine's load, not on the server).
  const auto accepted_after_flood = server.bridge().commands_accepted(0);
  const auto wait_start = Clock::now();
  while (server.bridge().commands_accepted(0) < accepted_after_flood + 100 && seconds_since(wait_start) < 10.0)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const auto accepted_later = server.bridge().commands_accepted(0);
  server.stop();
  server.join();
  std::printf("spoofed commands rejected as not the owner: %llu; the owner's accepted: %llu during, %llu after\n",
              static_cast<unsigned long long>(spoofed),
              static_cast<unsigned long long>(accepted_after_flood - accepted_before),
              static_cast<unsigned long long>(accepted_later - accepted_after_flood));
  EXPECT_GT(spoofed, 500u);  // the flood reached the server, and was rejected
  EXPECT_GE(accepted_later - accepted_after_flood, 100u);
  EXPECT_EQ(server.bridge().owner(0), "engine");
  EXPECT_EQ(server.bridge().rejected_by_reason(0)[static_cast<std::size_t>(dds::RejectReason::out_of_order)], 0u);
  // The device never felt the spoofed 60 N (the owner's proxy on the free handle gives a few newtons at most).
  double largest = 0.0;
  for (const auto& f : server.recording().force()) largest = std::max(largest, f.norm());
  EXPECT_LT(largest, 10.0);
}

TEST(DdsOwnership, AClaimEndsWhenItsClaimantExitsWithoutReleasing) {
  Server server(session_yaml(72, 60.0, "constant", "[0.0, 0.0, 0.0]", "realtime"));
  server.start();
  Client watcher({"watcher", 72});
  ASSERT_TRUE(watcher.wait_for_state("v3", std::chrono::seconds(20)));
  {
    Client quitter({"quitter", 72});
    ASSERT_TRUE(quitter.claim("v3").accepted);
    ASSERT_TRUE(wait_for_owner(watcher, "quitter", 2.0));
    EXPECT_FALSE(watcher.claim("v3").accepted);
  }  // gone without RELEASE
  const auto gone = Clock::now();
  const auto freed = wait_for_owner(watcher, "", 5.0);
  ASSERT_TRUE(freed.has_value()) << "the claim outlived its claimant";
  const client::Reply r = watcher.claim("v3");
  const double claimed_after = seconds_since(gone);
  EXPECT_TRUE(r.accepted) << r.message;
  std::printf("clean exit without release: device free after %.3f s, claimed by another client after %.3f s\n", *freed,
              claimed_after);
  EXPECT_LE(*freed, 1.0);
  EXPECT_EQ(server.bridge().claims_ended(), 1u);
  server.stop();
}

// The session with the claim's hold set (dds.claim_hold_s).
std::string with_claim_hold(std::string yaml, double hold_s) {
  const std::string key = "lockstep_wait_s: 2}";
  yaml.replace(yaml.find(key), key.size(), "lockstep_wait_s: 2, claim_hold_s: " + std::to_string(hold_s) + "}");
  return yaml;
}

TEST(DdsOwnership, AClaimEndsWhenItsClaimantIsKilledOrFrozenBeyondTheHold) {
  // The claim's hold here 2 s: a claimant whose participant stays but whose command writer lost its liveliness
  // (the 0.5 s lease) keeps the claim that long, then loses it.
  constexpr double kHold = 2.0;
  Server server(with_claim_hold(session_yaml(73, 60.0, "constant", "[0.0, 0.0, 0.0]", "realtime"), kHold));
  server.start();
  Client watcher({"watcher", 73});
  ASSERT_TRUE(watcher.wait_for_state("v3", std::chrono::seconds(20)));
  const auto measure = [&](const char* what, Process& claimant, const std::string& id, int sig) {
    ASSERT_TRUE(claimant.started());
    ASSERT_TRUE(wait_for_owner(watcher, id, 15.0)) << what << ": never claimed";
    claimant.signal(sig);
    const auto freed = wait_for_owner(watcher, "", kHold + 5.0);
    ASSERT_TRUE(freed.has_value()) << what << ": the claim outlived its claimant";
    std::printf("%s: device free after %.3f s (hold %.1f s)\n", what, *freed, kHold);
    EXPECT_GE(*freed, kHold) << what << ": the claim ended within its hold";
    EXPECT_LE(*freed, kHold + 1.5) << what;
    const client::Reply r = watcher.claim("v3");
    EXPECT_TRUE(r.accepted) << what << ": " << r.message;
    EXPECT_TRUE(watcher.release("v3").accepted);
  };
  const std::string domain = "73";
  {
    Process holder({bin("hapticctl"), "--domain", domain, "--id", "holder", "claim", "v3", "--hold", "60"});
    measure("claimed, killed before any command", holder, "holder", SIGKILL);
  }
  {
    Process holder({bin("hapticctl"), "--domain", domain, "--id", "sleeper", "claim", "v3", "--hold", "60"});
    measure("claimed, frozen (SIGSTOP)", holder, "sleeper", SIGSTOP);
  }
  {
    Process engine({bin("hapticd-scene-engine"), "--domain", domain, "--device", "v3", "--id", "scene"});
    ASSERT_TRUE(wait_for_owner(watcher, "scene", 15.0));
    const auto start = Clock::now();
    while (server.bridge().commands_accepted(0) < 100 && seconds_since(start) < 10.0)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_GE(server.bridge().commands_accepted(0), 100u);
    measure("engine killed after its commands", engine, "scene", SIGKILL);
  }
  EXPECT_EQ(server.bridge().claims_ended(), 3u);
  server.stop();
}

std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The text of `path` once it holds `what`, or after `seconds` (a process's line may follow what the test saw of
// it on DDS: the engine prints "claimed again" when its reply arrives, which can be after the state naming it).
std::string file_text_once_it_holds(const std::string& path, const std::string& what, double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  std::string text = file_text(path);
  while (text.find(what) == std::string::npos && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    text = file_text(path);
  }
  return text;
}

TEST(DdsOwnership, AnEngineWhoseClaimEndedIsToldAndClaimsAgainOrExits) {
  // The client library tells an engine that its claim ended (a state names another owner after one that named
  // it); the example engine claims again, or - another engine took the device meanwhile - exits 3 saying why.
  constexpr double kHold = 0.5;
  Server server(with_claim_hold(session_yaml(146, 60.0, "constant", "[0.0, 0.0, 0.0]", "realtime"), kHold));
  server.start();
  Client watcher({"watcher", 146});
  ASSERT_TRUE(watcher.wait_for_state("v3", std::chrono::seconds(20)));
  const std::string log = testing::TempDir() + "scene_engine_146.txt";
  {
    Process engine({bin("hapticd-scene-engine"), "--domain", "146", "--device", "v3", "--id", "scene"}, log);
    ASSERT_TRUE(wait_for_owner(watcher, "scene", 15.0));
    engine.signal(SIGSTOP);  // beyond the hold: the claim ends
    ASSERT_TRUE(wait_for_owner(watcher, "", kHold + 3.0)) << "the claim outlived the hold";
    engine.signal(SIGCONT);
    ASSERT_TRUE(wait_for_owner(watcher, "scene", 5.0)) << "the engine did not claim again: " << file_text(log);
    const std::string said = file_text_once_it_holds(log, "claimed 'v3' again", 5.0);
    EXPECT_NE(said.find("the server ended the claim of 'v3'"), std::string::npos) << said;
    EXPECT_NE(said.find("claimed 'v3' again"), std::string::npos) << said;
  }
  ASSERT_TRUE(wait_for_owner(watcher, "", kHold + 5.0));  // the killed engine's claim ends too
  {
    Process engine({bin("hapticd-scene-engine"), "--domain", "146", "--device", "v3", "--id", "scene"}, log);
    ASSERT_TRUE(wait_for_owner(watcher, "scene", 15.0));
    engine.signal(SIGSTOP);
    ASSERT_TRUE(wait_for_owner(watcher, "", kHold + 3.0));
    ASSERT_TRUE(watcher.claim("v3").accepted);  // another engine takes the device meanwhile
    engine.signal(SIGCONT);
    EXPECT_EQ(engine.wait_exit(10.0), 3) << file_text(log);
    EXPECT_NE(file_text(log).find("cannot claim 'v3' again"), std::string::npos) << file_text(log);
  }
  server.stop();
}

TEST(DdsOwnership, AClaimLostBeforeAnyStateNamedTheClaimantIsStillToldToIt) {
  // Found as a flaky run of the test above under a loaded machine: the engine was stopped right after its claim
  // was accepted, before its receive thread had taken a state naming it the owner; the client library told a
  // loss only after such a state, so the resumed engine never learned that its claim had ended and rendered on
  // with its commands rejected. Made certain here: a stand-in server on a domain of its own answers the claim,
  // announces it and then its end in owner events, and never publishes a state at all.
  constexpr int kDomain = 147;
  const dds::Participant server(dds::ParticipantOptions{kDomain, {}, {}});
  dds::Reader<hapticd_msg_ControlRequest> requests(server, {}, nullptr, {dds::target_partition("v3")});
  const dds::Writer<hapticd_msg_ControlReply> replies(server);
  const dds::Writer<hapticd_msg_Event> events(server);
  Client engine(client::ClientOptions("engine", kDomain));
  const auto owner_event = [&](const std::string& owner, std::uint64_t serial) {
    hapticd_msg_Event e{};
    dds::set_text(e.device, "v3");
    e.serial = serial;
    e.kind = hapticd_msg_EVENT_OWNER;
    dds::set_text(e.code, owner);
    dds::set_text(e.message, owner.empty() ? "the claim's hold ran out" : owner + " claimed the device");
    ASSERT_TRUE(events.write(e));
  };
  std::atomic<bool> answered{false};
  std::thread stand_in([&] {
    const auto start = Clock::now();
    while (!answered.load() && seconds_since(start) < 10.0) {
      requests.take([&](const hapticd_msg_ControlRequest& r, const dds_sample_info_t&) {
        if (r.kind != hapticd_msg_REQUEST_CLAIM || answered.load()) return;
        owner_event(std::string(dds::text_of(r.client)), 1);  // as the server: the event, then the reply
        hapticd_msg_ControlReply a{};
        dds::set_text(a.device, "v3");
        dds::set_text(a.client, dds::text_of(r.client));
        a.request_id = r.request_id;
        a.accepted = true;
        dds::set_text(a.message, "claimed");
        (void)replies.write(a);
        answered.store(true);
      });
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  const client::Reply claim = engine.claim("v3", std::chrono::seconds(8));
  stand_in.join();
  ASSERT_TRUE(claim.accepted) << claim.message;
  EXPECT_FALSE(engine.claim_lost("v3"));
  owner_event("", 2);  // the hold ran out
  const auto start = Clock::now();
  while (!engine.claim_lost("v3") && seconds_since(start) < 5.0)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_TRUE(engine.claim_lost("v3")) << "the engine was not told that its claim ended";
}

TEST(DdsOwnership, AnEngineFrozenShorterThanTheHoldKeepsItsClaimAndRendersAgain) {
  // The third hardening round, item 11: a rendering engine frozen for 0.8 s (a VR application loading a scene or
  // collecting garbage) lost its claim at the first command gap (the 0.5 s liveliness lease); resumed, its
  // commands were rejected as "not the owner" and its wall stopped rendering, and nobody was told. Now the claim
  // holds (the default hold, 5 s): the forces fade at the command deadline while it is frozen, and its commands
  // are taken again after.
  Server server(session_yaml(145, 60.0, "constant", "[0.0, 0.0, 0.0]", "realtime"));
  server.start();
  Client watcher({"watcher", 145});
  ASSERT_TRUE(watcher.wait_for_state("v3", std::chrono::seconds(20)));
  Process engine({bin("hapticd-scene-engine"), "--domain", "145", "--device", "v3", "--id", "scene"});
  ASSERT_TRUE(wait_for_owner(watcher, "scene", 15.0));
  const auto start = Clock::now();
  while (server.bridge().commands_accepted(0) < 200 && seconds_since(start) < 10.0)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const std::uint64_t before = server.bridge().commands_accepted(0);
  ASSERT_GE(before, 200u);
  engine.signal(SIGSTOP);
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  const std::uint64_t frozen = server.bridge().commands_accepted(0);
  engine.signal(SIGCONT);
  const auto resumed = Clock::now();
  while (server.bridge().commands_accepted(0) < frozen + 200 && seconds_since(resumed) < 5.0)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const std::uint64_t after = server.bridge().commands_accepted(0);
  std::printf("engine frozen 0.8 s: %llu commands accepted before, %llu after it resumed, owner '%s'\n",
              static_cast<unsigned long long>(before), static_cast<unsigned long long>(after - frozen),
              owner_seen(watcher).c_str());
  EXPECT_EQ(owner_seen(watcher), "scene") << "the stalled engine lost its claim";
  EXPECT_GE(after, frozen + 200) << "the resumed engine's commands were not taken";
  EXPECT_EQ(server.bridge().claims_ended(), 0u);
  server.stop();
}

}  // namespace
}  // namespace hapticd::server
