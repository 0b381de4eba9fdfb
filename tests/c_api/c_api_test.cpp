// The C API (hapticd/client.h) from C++: its error paths (every bad argument a status and a message, per
// thread; nothing aborts; DDS domain 150, empty), and against a server process on loopback (DDS domain 149, real time;
// a process of its own, as an engine meets it - a reader in this process would take each command through Cyclone's
// local delivery, which allocates): discovery, states, a claim and its refusal to another client, parameters, and the
// per-cycle calls - the latest state and a command - allocating nothing.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "hapticd/client.h"
#include "hapticd/testing/allocation_guard.hpp"
#include "support/child_process.hpp"
#include "support/sanitizers.hpp"
#include "support/test_paths.hpp"

namespace hapticd {
namespace {

constexpr int kDomain = 149;       // the server's
constexpr int kEmptyDomain = 150;  // nobody's: the error paths (ctest runs the two tests at once)
constexpr int kGroupDomain = 148;  // the pair's server

hapticd_client* make(const char* id, int domain = kDomain) {
  hapticd_client_options o{};
  o.size = sizeof o;
  o.client_id = id;
  o.domain_id = domain;
  hapticd_client* c = nullptr;
  EXPECT_EQ(hapticd_client_create(&o, &c), HAPTICD_OK) << hapticd_last_error();
  return c;
}

// hapticd on a shipped session of the simulated ViSHaRD3 (config/sessions/vishard3/SESSION) on `domain`, for 30 s,
// without real-time privileges and with the loop's watchdogs loosened (tests/e2e/session_copy.sh says why).
std::vector<std::string> served(const std::string& session, int domain) {
  return {test::bin_dir() + "/hapticd",
          "--config",
          test::source_dir() + "/config/sessions/vishard3/" + session,
          "--dds-domain",
          std::to_string(domain),
          "--duration",
          "30",
          "--set",
          "server.realtime_priority=0",
          "--set",
          "server.lock_memory=false",
          "--set",
          "devices.vishard3.safety.max_stall_s=1.0",
          "--set",
          "devices.vishard3.safety.max_consecutive_overruns=2000"};
}

hapticd_device_info& info_out() {
  static hapticd_device_info info;
  return info;
}

TEST(CApi, EveryBadArgumentIsAStatusWithAMessageNeverAnAbort) {
  EXPECT_EQ(hapticd_api_version(), HAPTICD_C_API_VERSION);
  hapticd_client* c = nullptr;
  EXPECT_EQ(hapticd_client_create(nullptr, &c), HAPTICD_ERROR_INVALID_ARGUMENT);
  hapticd_client_options o{};
  o.client_id = "options-without-size";
  o.domain_id = kEmptyDomain;
  EXPECT_EQ(hapticd_client_create(&o, &c), HAPTICD_ERROR_INVALID_ARGUMENT);  // no size: an older or unset struct
  EXPECT_NE(std::string(hapticd_last_error()).find("options->size"), std::string::npos) << hapticd_last_error();
  o.size = sizeof o;
  o.client_id = "";
  EXPECT_EQ(hapticd_client_create(&o, &c), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(hapticd_last_error()).find("the client id must have 1 to 31 characters"), std::string::npos);
  EXPECT_EQ(c, nullptr);
  o.client_id = "an-id-that-is-longer-than-thirty-one-characters";
  EXPECT_EQ(hapticd_client_create(&o, &c), HAPTICD_ERROR_INVALID_ARGUMENT);
  o.client_id = "c-api";
  o.domain_id = 231;
  EXPECT_EQ(hapticd_client_create(&o, &c), HAPTICD_ERROR_INVALID_ARGUMENT);
  o.domain_id = kEmptyDomain;
  o.command_deadline_s = std::nan("");
  EXPECT_EQ(hapticd_client_create(&o, &c), HAPTICD_ERROR_INVALID_ARGUMENT);
  o.command_deadline_s = 0.0;
  o.network = "interfaces=;bogus";  // the library refuses the network text, and says why
  EXPECT_EQ(hapticd_client_create(&o, &c), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_STRNE(hapticd_last_error(), "");
  o.network = nullptr;
  // Hardening round 4, item 8: a Cyclone configuration that never ends (/dev/zero: read without limit before) or a
  // named pipe (waited on for ever) is refused at once, and says why.
  const std::string fifo = ::testing::TempDir() + "c_api_cyclone_fifo";
  (void)std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& endless : {std::string("/dev/zero"), fifo}) {
    // On a thread of its own, bounded: a create that hangs (the old code waited on the pipe) fails the test.
    auto done = std::make_shared<std::atomic<bool>>(false);
    auto result = std::make_shared<std::pair<hapticd_status, std::string>>();
    std::thread([endless, o, done, result]() mutable {
      o.cyclone_config = endless.c_str();
      hapticd_client* made = nullptr;
      result->first = hapticd_client_create(&o, &made);
      result->second = hapticd_last_error();
      hapticd_client_destroy(made);
      done->store(true);
    }).detach();
    for (int i = 0; i < 500 && !done->load(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!done->load()) {
      std::fprintf(stderr, "FAILED: hapticd_client_create with cyclone_config %s hangs\n", endless.c_str());
      std::_Exit(1);  // a hung thread cannot be joined
    }
    EXPECT_NE(result->first, HAPTICD_OK);
    EXPECT_NE(result->second.find("not a regular file"), std::string::npos) << result->second;
  }
  (void)std::remove(fifo.c_str());
  o.cyclone_config = nullptr;

  c = make("c-api-errors", kEmptyDomain);
  ASSERT_NE(c, nullptr);
  hapticd_device_state state;
  hapticd_reply reply;
  EXPECT_EQ(hapticd_client_latest_state(c, nullptr, &state), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_latest_state(c, "vishard3", nullptr), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_latest_state(nullptr, "vishard3", &state), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_latest_state(c, "nobody", &state), HAPTICD_ERROR_NOT_FOUND);
  EXPECT_EQ(hapticd_client_wait_for_state(c, "nobody", 0.1, 0, &state), HAPTICD_ERROR_TIMEOUT);
  EXPECT_EQ(hapticd_client_wait_for_state(c, "vishard3", -1.0, 0, &state), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_wait_for_state(c, "vishard3", INFINITY, 0, &state), HAPTICD_ERROR_INVALID_ARGUMENT);
  // Nobody drives "nobody": the request goes unanswered.
  EXPECT_EQ(hapticd_client_claim(c, "nobody", 0.3, &reply), HAPTICD_ERROR_TIMEOUT);
  EXPECT_EQ(reply.answered, 0);
  const double values[17] = {};
  EXPECT_EQ(hapticd_client_set_parameter(c, "vishard3", "virtual_model.mass_kg", values, 17, 0.1, &reply),
            HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_set_parameter(c, "vishard3", "virtual_model.mass_kg", nullptr, 3, 0.1, &reply),
            HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_get_parameter(c, "vishard3", nullptr, 0.1, &reply), HAPTICD_ERROR_INVALID_ARGUMENT);
  hapticd_command command{};
  command.kind = 7;
  EXPECT_EQ(hapticd_client_send(c, "vishard3", &command), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(hapticd_last_error()).find("unknown command kind"), std::string::npos);
  EXPECT_EQ(hapticd_client_send_group(c, "g", &command, 0), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_send_group(c, "g", &command, 9), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_send_coupling(c, "vishard3", nullptr, nullptr, 0), HAPTICD_ERROR_INVALID_ARGUMENT);
  int32_t count = -1;
  EXPECT_EQ(hapticd_client_list_devices(c, nullptr, 4, &count), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_list_devices(c, nullptr, 0, &count), HAPTICD_OK);
  EXPECT_EQ(count, 0);
  hapticd_event events[4];
  EXPECT_EQ(hapticd_client_take_events(c, events, -1, &count), HAPTICD_ERROR_INVALID_ARGUMENT);
  int32_t lost = -1;
  EXPECT_EQ(hapticd_client_claim_lost(c, nullptr, &lost), HAPTICD_ERROR_INVALID_ARGUMENT);  // was 0 "not lost"
  EXPECT_EQ(hapticd_client_claim_lost(c, "vishard3", nullptr), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_claim_lost(nullptr, "vishard3", &lost), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(lost, -1);
  EXPECT_EQ(hapticd_client_claim_lost(c, "vishard3", &lost), HAPTICD_OK);
  EXPECT_EQ(lost, 0);
  EXPECT_EQ(hapticd_client_on_state(c, "an-id-that-is-longer-than-thirty-one-characters", nullptr, nullptr),
            HAPTICD_ERROR_INVALID_ARGUMENT);
  // The engine helper.
  hapticd_engine* engine = nullptr;
  hapticd_engine_options eo{};
  EXPECT_EQ(hapticd_engine_create(c, &eo, &engine), HAPTICD_ERROR_INVALID_ARGUMENT);  // no size
  EXPECT_NE(std::string(hapticd_last_error()).find("options->size"), std::string::npos);
  eo.size = sizeof eo;
  eo.device = "an-id-that-is-longer-than-thirty-one-characters";
  EXPECT_EQ(hapticd_engine_create(c, &eo, &engine), HAPTICD_ERROR_INVALID_ARGUMENT);
  eo.device = "vishard3";
  eo.group = "hands";
  EXPECT_EQ(hapticd_engine_create(c, &eo, &engine), HAPTICD_ERROR_INVALID_ARGUMENT);
  eo.group = nullptr;
  eo.wait_s = std::nan("");
  EXPECT_EQ(hapticd_engine_create(c, &eo, &engine), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(engine, nullptr);
  EXPECT_EQ(hapticd_engine_create(nullptr, &eo, &engine), HAPTICD_ERROR_INVALID_ARGUMENT);
  eo.device = "nobody";
  eo.wait_s = 0.2;
  ASSERT_EQ(hapticd_engine_create(c, &eo, &engine), HAPTICD_OK) << hapticd_last_error();
  EXPECT_EQ(hapticd_engine_run(engine, nullptr, nullptr, nullptr), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_engine_device(engine, 0, &info_out()), HAPTICD_ERROR_NOT_FOUND);  // not connected
  hapticd_engine_end end{};
  const auto answer_nothing = [](const hapticd_device_state*, int32_t, hapticd_command*, void*) -> int32_t {
    return 0;
  };
  EXPECT_EQ(hapticd_engine_run(engine, answer_nothing, nullptr, &end), HAPTICD_OK);  // nobody drives "nobody"
  EXPECT_EQ(end.reason, HAPTICD_ENGINE_NO_DEVICE);
  EXPECT_EQ(end.exit_code, 1);
  EXPECT_EQ(hapticd_engine_run(engine, answer_nothing, nullptr, &end), HAPTICD_ERROR_INVALID_ARGUMENT);  // once
  EXPECT_EQ(hapticd_engine_stop(nullptr), HAPTICD_ERROR_INVALID_ARGUMENT);
  std::uint64_t answered = 7;
  EXPECT_EQ(hapticd_engine_answered(nullptr, &answered), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_engine_answered(engine, nullptr), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_engine_answered(engine, &answered), HAPTICD_OK);
  EXPECT_EQ(answered, 0u);
  int32_t devices = -1;
  EXPECT_EQ(hapticd_engine_device_count(nullptr, &devices), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_engine_device_count(engine, &devices), HAPTICD_OK);
  EXPECT_EQ(devices, 0);
  hapticd_engine_destroy(engine);
  hapticd_engine_destroy(nullptr);
  EXPECT_STREQ(hapticd_status_name(HAPTICD_ERROR_TIMEOUT), "HAPTICD_ERROR_TIMEOUT");
  EXPECT_STREQ(hapticd_status_name(static_cast<hapticd_status>(99)), "an unknown status");

  // The message is the calling thread's own.
  EXPECT_EQ(hapticd_client_latest_state(c, "", &state), HAPTICD_ERROR_INVALID_ARGUMENT);
  std::string other = "unset";
  std::thread([&] { other = hapticd_last_error(); }).join();
  EXPECT_EQ(other, "");
  EXPECT_NE(std::string(hapticd_last_error()).find("the device must have 1 to 31 characters"), std::string::npos);
  hapticd_client_destroy(c);
  hapticd_client_destroy(nullptr);
}

TEST(CApi, AnEngineDiscoversClaimsAndAnswersStatesWithoutAllocating) {
  const std::string log = ::testing::TempDir() + "c_api_server.txt";
  test::Process server(served("dds-coupling.yaml", kDomain), log);
  ASSERT_TRUE(server.started());
  hapticd_client* c = make("c-api-engine");
  hapticd_client* other = make("c-api-other");
  ASSERT_NE(c, nullptr);
  ASSERT_NE(other, nullptr);
  hapticd_device_info info;
  ASSERT_EQ(hapticd_client_wait_for_device(c, "vishard3", 20.0, 1, &info), HAPTICD_OK) << hapticd_last_error();
  EXPECT_STREQ(info.device, "vishard3");
  EXPECT_EQ(info.dof, 3);
  EXPECT_EQ(info.has_start_pose, 1);
  EXPECT_EQ(info.simulated, 1);
  EXPECT_GT(info.scheme_count, 0);
  int32_t count = 0;
  hapticd_device_info listed[2];
  ASSERT_EQ(hapticd_client_list_devices(c, listed, 2, &count), HAPTICD_OK);
  EXPECT_EQ(count, 1);
  hapticd_device_state state;
  ASSERT_EQ(hapticd_client_wait_for_state(c, "vishard3", 10.0, 0, &state), HAPTICD_OK) << hapticd_last_error();
  EXPECT_STREQ(state.device, "vishard3");
  EXPECT_EQ(state.dof, 3);
  EXPECT_NEAR(state.pose.position.x, info.start_pose.position.x, 0.01);
  // Hardening round 4, item 9: a timeout of 1e10 s or more overflowed the clock and returned TIMEOUT at once; it
  // waits (here for a state 200 serials on, a fraction of a second away).
  for (const double long_timeout : {1e10, 1e300}) {
    const std::uint64_t after = state.serial + 200;
    ASSERT_EQ(hapticd_client_wait_for_state(c, "vishard3", long_timeout, after, &state), HAPTICD_OK)
        << hapticd_last_error();
    EXPECT_GT(state.serial, after);
  }

  hapticd_reply reply;
  ASSERT_EQ(hapticd_client_claim(c, "vishard3", 5.0, &reply), HAPTICD_OK) << hapticd_last_error();
  EXPECT_EQ(reply.accepted, 1);
  EXPECT_EQ(hapticd_client_claim(other, "vishard3", 5.0, &reply), HAPTICD_ERROR_REFUSED);
  EXPECT_EQ(reply.answered, 1);
  EXPECT_NE(std::string(hapticd_last_error()).find("c-api-engine"), std::string::npos) << hapticd_last_error();

  const double stiffness = 2500.0;
  ASSERT_EQ(hapticd_client_set_parameter(c, "vishard3", "virtual_model.coupling_stiffness_n_per_m", &stiffness, 1, 5.0,
                                         &reply),
            HAPTICD_OK)
      << hapticd_last_error();
  ASSERT_EQ(hapticd_client_get_parameter(c, "vishard3", "virtual_model.coupling_stiffness_n_per_m", 5.0, &reply),
            HAPTICD_OK);
  ASSERT_EQ(reply.value_count, 1);
  EXPECT_EQ(reply.values[0], 2500.0);
  hapticd_parameter_info parameter;
  ASSERT_EQ(hapticd_client_describe_parameter(c, "vishard3", "virtual_model.coupling_stiffness_n_per_m", 5.0,
                                              &parameter, &reply),
            HAPTICD_OK);
  EXPECT_STREQ(parameter.unit, "N/m");
  EXPECT_EQ(parameter.tunable, 1);
  EXPECT_EQ(parameter.type, HAPTICD_PARAMETER_REAL);
  EXPECT_EQ(hapticd_client_get_parameter(c, "vishard3", "virtual_model.no_such_parameter", 5.0, &reply),
            HAPTICD_ERROR_REFUSED);

  // The per-cycle calls: the newest state, and a coupling command answering it.
  ASSERT_EQ(hapticd_client_wait_for_state(c, "vishard3", 5.0, state.serial, &state), HAPTICD_OK);
  const hapticd_twist still{};
  if (hapticd::testing::AllocationGuard::available()) {
    std::size_t reading = 0, sending = 0;
    for (int i = 0; i < 200; ++i) {
      reading += hapticd::testing::count_allocations(
          [&] { ASSERT_EQ(hapticd_client_latest_state(c, "vishard3", &state), HAPTICD_OK); });
      sending += hapticd::testing::count_allocations([&] {
        ASSERT_EQ(hapticd_client_send_coupling(c, "vishard3", &state.pose, &still, state.serial), HAPTICD_OK);
      });
    }
    EXPECT_EQ(reading, 0u);
    EXPECT_EQ(sending, 0u);
  }
  // The server took the commands: the state says the engine is active.
  bool active = false;
  for (int i = 0; i < 200 && !active; ++i) {
    ASSERT_EQ(hapticd_client_latest_state(c, "vishard3", &state), HAPTICD_OK);
    ASSERT_EQ(hapticd_client_send_coupling(c, "vishard3", &state.pose, &still, state.serial), HAPTICD_OK);
    active = (state.flags & HAPTICD_FLAG_ENGINE_ACTIVE) != 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_TRUE(active);
  EXPECT_STREQ(state.owner, "c-api-engine");
  hapticd_telemetry telemetry{};
  for (int i = 0; i < 60 && !(hapticd_client_latest_telemetry(c, "vishard3", &telemetry) == HAPTICD_OK &&
                              telemetry.commands_accepted > 0);
       ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_GT(telemetry.commands_accepted, 0u);
  EXPECT_EQ(hapticd_client_release(c, "vishard3", 5.0, &reply), HAPTICD_OK);
  hapticd_event events[64];
  int32_t taken = 0;
  ASSERT_EQ(hapticd_client_take_events(c, events, 64, &taken), HAPTICD_OK);
  bool owner_event = false;
  for (int i = 0; i < taken; ++i) owner_event |= events[i].kind == HAPTICD_EVENT_OWNER;
  EXPECT_TRUE(owner_event);
  hapticd_client_destroy(other);
  hapticd_client_destroy(c);
}

// Version 2 of the C API: a group is claimed, stopped, recovered and released through the device calls, and a state
// callback takes the states of the device it names (the C# engine compared names byte by byte per state).
TEST(CApi, GroupRequestsGoThroughTheDeviceCallsAndAStateCallbackTakesOnlyItsDevice) {
  const std::string log = ::testing::TempDir() + "c_api_group_server.txt";
  test::Process server(
      {test::bin_dir() + "/hapticd", "--config", test::source_dir() + "/config/sessions/dual-arm/vishard3-pair.yaml",
       "--dds-domain", std::to_string(kGroupDomain), "--duration", "30", "--busy-machine", "--set",
       "server.realtime_priority=0", "--set", "server.lock_memory=false"},
      log);
  ASSERT_TRUE(server.started());
  hapticd_client* c = make("c-api-pair", kGroupDomain);
  hapticd_client* other = make("c-api-pair-other", kGroupDomain);
  ASSERT_NE(c, nullptr);
  ASSERT_NE(other, nullptr);
  hapticd_device_state state;
  ASSERT_EQ(hapticd_client_wait_for_state(c, "right", 20.0, 0, &state), HAPTICD_OK) << hapticd_last_error();

  // The filter: only "right"'s states reach the callback, while both devices publish.
  struct Seen {
    std::atomic<int> right{0}, others{0};
  } seen;
  const auto count = [](const hapticd_device_state* s, void* user) {
    auto* into = static_cast<Seen*>(user);
    (std::string(s->device) == "right" ? into->right : into->others)++;
  };
  ASSERT_EQ(hapticd_client_on_state(c, "right", count, &seen), HAPTICD_OK) << hapticd_last_error();
  for (int i = 0; i < 200 && seen.right < 50; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(hapticd_client_on_state(c, nullptr, nullptr, nullptr), HAPTICD_OK);
  EXPECT_GE(seen.right.load(), 50);
  EXPECT_EQ(seen.others.load(), 0);
  ASSERT_EQ(hapticd_client_latest_state(c, "left", &state), HAPTICD_OK);  // "left" was publishing all along

  // The group through hapticd_client_claim: both devices are the client's; a device of it is refused to another.
  hapticd_reply reply;
  ASSERT_EQ(hapticd_client_claim(c, "table", 5.0, &reply), HAPTICD_OK) << hapticd_last_error();
  for (const char* device : {"left", "right"}) {
    bool owned = false;
    for (int i = 0; i < 200 && !owned; ++i) {
      ASSERT_EQ(hapticd_client_latest_state(c, device, &state), HAPTICD_OK);
      owned = std::string(state.owner) == "c-api-pair";
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_TRUE(owned) << device;
  }
  EXPECT_EQ(hapticd_client_claim(other, "left", 5.0, &reply), HAPTICD_ERROR_REFUSED);
  // A stop of the group stops both; its recover recovers both.
  ASSERT_EQ(hapticd_client_emergency_stop(c, "table", 5.0, &reply), HAPTICD_OK) << hapticd_last_error();
  for (const char* device : {"left", "right"}) {
    bool stopped = false;
    for (int i = 0; i < 200 && !stopped; ++i) {
      ASSERT_EQ(hapticd_client_latest_state(c, device, &state), HAPTICD_OK);
      stopped = (state.flags & HAPTICD_FLAG_ESTOP) != 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_TRUE(stopped) << device;
  }
  bool recovered = false;
  for (int i = 0; i < 50 && !recovered; ++i) {  // once zero torque is reached
    recovered = hapticd_client_recover(c, "table", 5.0, &reply) == HAPTICD_OK;
    if (!recovered) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(recovered) << hapticd_last_error();
  ASSERT_EQ(hapticd_client_release(c, "table", 5.0, &reply), HAPTICD_OK) << hapticd_last_error();
  EXPECT_EQ(hapticd_client_claim(other, "left", 5.0, &reply), HAPTICD_OK) << hapticd_last_error();
  hapticd_client_destroy(other);
  hapticd_client_destroy(c);
}

// The session's haptic scene through the C API (hapticd_client_scene_*) against a real server on
// vishard3/dds-scene.yaml: the owner's wall holds the simulated operator's push, the contacts and the listing come
// back as the C structs, a mesh goes up from C arrays, and what is bad is a status with the reason.
TEST(CApi, TheScenesCallsEditTheSessionsSceneAndSayWhyWhenRefused) {
  // The sanitizer builds (scripts/sanitize.sh) do not build the scene's plugin (Embree, Assimp: not instrumented).
  if (test::kSanitized) GTEST_SKIP() << "the sanitizer builds have no haptic_scene plugin for the server to load";
  constexpr int kSceneDomain = 160;
  const std::string log = ::testing::TempDir() + "c_api_scene_server.txt";
  test::Process server(served("dds-scene.yaml", kSceneDomain), log);
  ASSERT_TRUE(server.started());
  hapticd_client* c = make("c-scene-engine", kSceneDomain);
  hapticd_client* other = make("c-scene-other", kSceneDomain);
  ASSERT_NE(c, nullptr);
  ASSERT_NE(other, nullptr);
  hapticd_device_info info;
  ASSERT_EQ(hapticd_client_wait_for_device(c, "vishard3", 20.0, 1, &info), HAPTICD_OK) << hapticd_last_error();
  hapticd_device_state state;
  ASSERT_EQ(hapticd_client_wait_for_state(c, "vishard3", 10.0, 0, &state), HAPTICD_OK) << hapticd_last_error();
  const hapticd_vec3 start = state.pose.position;

  hapticd_reply reply;
  EXPECT_EQ(hapticd_client_scene_add(c, "{\"name\": \"x\", \"shape\": \"sphere\", \"radius\": 0.01}", 5.0, &reply),
            HAPTICD_ERROR_REFUSED);
  EXPECT_STREQ(hapticd_last_error(), "claim the scene first");
  ASSERT_EQ(hapticd_client_scene_claim(c, 5.0, &reply), HAPTICD_OK) << hapticd_last_error();
  EXPECT_EQ(hapticd_client_scene_claim(other, 5.0, &reply), HAPTICD_ERROR_REFUSED);
  EXPECT_NE(std::string(reply.message).find("c-scene-engine"), std::string::npos) << reply.message;

  char wall[512];
  std::snprintf(wall, sizeof wall,
                R"({"name": "wall", "shape": "plane", "position": [%.6f, %.6f, %.6f], "normal": [-1, 0, 0],
                    "material": {"stiffness": 3000, "damping": 5}})",
                start.x + 0.02, start.y, start.z);
  ASSERT_EQ(hapticd_client_scene_add(c, wall, 5.0, &reply), HAPTICD_OK) << hapticd_last_error();
  const double push[] = {15.0, 0.0, 0.0, 0.3};
  ASSERT_EQ(hapticd_client_operator_command(c, "vishard3", "push", push, 4, 5.0, &reply), HAPTICD_OK);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  hapticd_scene_contact contacts[4];
  int32_t count = 0;
  ASSERT_EQ(hapticd_client_scene_contacts(other, contacts, 4, &count, 5.0, &reply), HAPTICD_OK) << hapticd_last_error();
  ASSERT_EQ(count, 1);
  EXPECT_STREQ(contacts[0].device, "vishard3");
  EXPECT_STREQ(contacts[0].object_name, "wall");
  ASSERT_EQ(hapticd_client_wait_for_state(c, "vishard3", 5.0, 0, &state), HAPTICD_OK);
  const double held = state.pose.position.x - start.x;
  std::printf("the wall holds the push: the handle at %.2f mm, pressing the wall with %.2f N\n", 1e3 * held,
              contacts[0].force.x);
  EXPECT_GT(contacts[0].force.x, 5.0);
  EXPECT_NEAR(held, 0.015 + contacts[0].force.x / 3000, 0.001);

  // A mesh from C arrays (one triangle far away), a moving block, the listing; the count without room for them.
  const double vertices[] = {0, -0.01, -0.01, 0, 0.01, -0.01, 0, 0, 0.01};
  const uint32_t triangle[] = {0, 1, 2};
  ASSERT_EQ(hapticd_client_scene_add_mesh(c, R"({"name": "shard", "shape": "mesh", "position": [0.5, 0, 0]})", vertices,
                                          3, triangle, 1, 5.0, &reply),
            HAPTICD_OK)
      << hapticd_last_error();
  ASSERT_EQ(
      hapticd_client_scene_add(
          c,
          R"({"name": "block", "shape": "box", "size": [0.02, 0.02, 0.02], "position": [0.6, 0, 0], "moving": true})",
          5.0, &reply),
      HAPTICD_OK)
      << hapticd_last_error();
  ASSERT_EQ(hapticd_client_scene_objects(c, nullptr, 0, &count, 5.0, &reply), HAPTICD_OK);
  EXPECT_EQ(count, 3);
  hapticd_scene_object objects[3];
  ASSERT_EQ(hapticd_client_scene_objects(c, objects, 3, &count, 5.0, &reply), HAPTICD_OK);
  EXPECT_STREQ(objects[1].name, "shard");
  EXPECT_STREQ(objects[1].shape, "mesh");
  EXPECT_EQ(objects[1].triangles, 1u);
  EXPECT_EQ(objects[2].moving, 1);
  EXPECT_NEAR(objects[2].pose.position.x, 0.6, 1e-9);
  hapticd_pose to{{0.6, 0.01, 0.0}, {1.0, 0.0, 0.0, 0.0}};
  EXPECT_EQ(hapticd_client_scene_move(c, "block", &to), HAPTICD_OK);
  EXPECT_EQ(hapticd_client_scene_move(c, "wall", &to), HAPTICD_OK);  // written; refused by the server (not moving)
  uint64_t refused = 0;
  char why[128];
  for (int i = 0; i < 500 && refused == 0; ++i) {
    ASSERT_EQ(hapticd_client_scene_refused_moves(c, &refused, why, sizeof why), HAPTICD_OK);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(refused, 1u);
  EXPECT_NE(std::string(why).find("moving"), std::string::npos) << why;

  // Refused by the server, with the reason; bad arguments never leave the process.
  EXPECT_EQ(hapticd_client_scene_add(c, R"({"name": "ball", "shape": "sphere", "radius": -1})", 5.0, &reply),
            HAPTICD_ERROR_REFUSED);
  EXPECT_NE(std::string(reply.message).find("radius"), std::string::npos) << reply.message;
  EXPECT_EQ(hapticd_client_scene_remove(other, "wall", 5.0, &reply), HAPTICD_ERROR_REFUSED);
  EXPECT_EQ(hapticd_client_scene_set_material(c, "wall", "a: &x [1]\nb: *x", 5.0, &reply), HAPTICD_ERROR_REFUSED);
  EXPECT_EQ(hapticd_client_scene_add(c, nullptr, 5.0, &reply), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_add(nullptr, wall, 5.0, &reply), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_add(c, wall, -1.0, &reply), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_add(c, wall, std::nan(""), &reply), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_add_mesh(c, "{}", nullptr, 3, triangle, 1, 5.0, &reply),
            HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_add_mesh(c, "{}", vertices, -1, triangle, 1, 5.0, &reply),
            HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_move(c, "block", nullptr), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_move(c, "", &to), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_remove(c, "a-name-of-more-than-thirty-one-characters", 5.0, &reply),
            HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_objects(c, nullptr, 2, &count, 5.0, &reply), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_contacts(c, contacts, 4, nullptr, 5.0, &reply), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_refused_moves(c, nullptr, nullptr, 0), HAPTICD_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(hapticd_client_scene_release(c, 5.0, &reply), HAPTICD_OK);
  EXPECT_EQ(hapticd_client_scene_claim(other, 5.0, &reply), HAPTICD_OK) << hapticd_last_error();
  hapticd_client_destroy(other);
  hapticd_client_destroy(c);
}

}  // namespace
}  // namespace hapticd
