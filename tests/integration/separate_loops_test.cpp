// Groups on loop threads of their own (`groups[i].loop`): in real time each such group runs on a thread of its
// own beside the session's loop (structural checks only: every device runs every period of its loop and is
// recorded; nothing about this machine's speed); in lockstep every loop runs on one thread, and the run is the
// same bit for bit as without the setting.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "app/served_session.hpp"
#include "support/recording.hpp"
#include "support/temp_file.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

std::string four_devices(const std::string& clock, const std::string& loops) {
  return "server: {clock: " + clock + ", rate_hz: 2000, duration_s: 0.2, shutdown_ramp_s: 0.02, seed: 3}\ndevices:\n" +
         test::mass_spring_device_yaml("a", ", position_noise_m: 1.0e-4") +
         test::mass_spring_device_yaml("b", ", position_noise_m: 1.0e-4") +
         test::mass_spring_device_yaml("c", ", position_noise_m: 1.0e-4") +
         test::mass_spring_device_yaml("d", ", position_noise_m: 1.0e-4") +
         "groups:\n  - name: first\n    devices: [a, b]\n" + loops + "  - name: second\n    devices: [c]\n" + loops;
}

struct Served {
  ExecutorResult result;
  std::map<std::string, std::string> recording;  // device -> its cycles as CSV
};

Served serve(const std::string& yaml, const std::string& record_name) {
  Session s = test::build_test_session(yaml);
  ServeOptions options;
  options.realtime_setup = false;  // no SCHED_FIFO or pinning on a shared test machine
  options.record_file = test::write_temp_file(record_name, "");
  ServedSession served(s.impl().config, s.impl().device_pointers(), s.impl().stage_pointers(), options);
  std::atomic<bool> stop{false};
  Served out;
  out.result = served.run(stop);
  EXPECT_EQ(served.recorder()->dropped(), 0u);
  served.recorder()->close();
  out.recording = test::recording_csv(options.record_file);
  return out;
}

// Rows per device in a recording (one per cycle).
std::map<std::string, std::uint64_t> rows_per_device(const std::map<std::string, std::string>& csv) {
  std::map<std::string, std::uint64_t> rows;
  for (const auto& [device, text] : csv)
    rows[device] = static_cast<std::uint64_t>(std::count(text.begin(), text.end(), '\n')) - 1;  // less the header
  return rows;
}

TEST(SeparateLoops, InRealTimeEachGroupWithALoopRunsOnItsOwnBesideTheSessionsLoop) {
  const Served s = serve(four_devices("realtime", "    loop: {}\n"), "loops.h5");
  ASSERT_EQ(s.result.loops.size(), 3u);
  EXPECT_EQ(s.result.loops[0].name, "session");
  EXPECT_EQ(s.result.loops[0].devices, std::vector<std::string>({"d"}));
  EXPECT_EQ(s.result.loops[1].name, "first");
  EXPECT_EQ(s.result.loops[1].devices, std::vector<std::string>({"a", "b"}));
  EXPECT_EQ(s.result.loops[2].name, "second");
  EXPECT_EQ(s.result.loops[2].devices, std::vector<std::string>({"c"}));
  std::uint64_t cycles = 0;
  for (const LoopResult& l : s.result.loops) {
    // Each loop accounts for every period of the session: the duration and the ramp, run or skipped.
    EXPECT_EQ(l.statistics.cycles + l.statistics.skipped_cycles, l.periods) << l.name;
    EXPECT_GE(l.periods, 400u + 40u) << l.name;
    EXPECT_EQ(l.statistics.compute_time.count(), l.statistics.cycles) << l.name;
    cycles += l.statistics.cycles;
  }
  EXPECT_EQ(s.result.statistics.cycles, cycles);  // the session's figures are every loop's together
  // Each device is recorded every cycle of its loop, whatever loop records it.
  const auto rows = rows_per_device(s.recording);
  EXPECT_EQ(rows.at("d"), s.result.loops[0].statistics.cycles);
  EXPECT_EQ(rows.at("a"), s.result.loops[1].statistics.cycles);
  EXPECT_EQ(rows.at("b"), s.result.loops[1].statistics.cycles);
  EXPECT_EQ(rows.at("c"), s.result.loops[2].statistics.cycles);
}

TEST(SeparateLoops, InLockstepEveryLoopRunsOnOneThreadAndTheRunIsUnchanged) {
  const Served with = serve(four_devices("lockstep", "    loop: {cpu: 0}\n"), "with.h5");
  const Served without = serve(four_devices("lockstep", ""), "without.h5");
  ASSERT_EQ(with.result.loops.size(), 1u);
  EXPECT_EQ(with.result.loops[0].devices, std::vector<std::string>({"a", "b", "c", "d"}));
  EXPECT_EQ(with.result.loops[0].cpu, -1);
  EXPECT_EQ(with.result.statistics.cycles, 440u);
  EXPECT_GT(with.recording.at("a").size(), 50'000u);
  EXPECT_TRUE(with.recording == without.recording) << "a group's loop setting changed a lockstep run";
}

TEST(SeparateLoops, TheLoopSettingIsCheckedInTheSessionFile) {
  const auto error_of = [](const std::string& loop) {
    try {
      (void)test::build_test_session(four_devices("lockstep", loop));
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("    loop: 3\n").find("groups[0].loop"), std::string::npos);
  EXPECT_NE(error_of("    loop: {cpu: -2}\n").find("groups[0].loop.cpu"), std::string::npos);
  EXPECT_NE(error_of("    loop: {cores: 1}\n").find("groups[0].loop"), std::string::npos);
}

}  // namespace
}  // namespace hapticd::server
