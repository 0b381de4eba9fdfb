// The loop in lockstep (deterministic, machine-independent) and briefly in real time (structural checks only:
// no assertion on how fast this machine is).
#include "executor/executor.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "app/served_session.hpp"
#include "recorder/recorder.hpp"
#include "support/recording.hpp"
#include "support/temp_file.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

std::string lockstep_yaml(double duration_s, const std::string& devices, std::uint64_t seed = 1) {
  return "server: {clock: lockstep, rate_hz: 2000, duration_s: " + std::to_string(duration_s) +
         ", shutdown_ramp_s: 0.1, seed: " + std::to_string(seed) + "}\ndevices:\n" + devices;
}

// Runs a session and returns its recording (both devices' cycles as CSV, without the machine's timing).
std::string run_recorded(const std::string& yaml, const std::string& record_name) {
  auto s = test::build_test_session(yaml);
  const auto file = test::write_temp_file(record_name, "");
  Recorder recorder(file, recording_header(s.impl().config, s.impl().device_pointers()), /*wait_when_full=*/true);
  const LoopPlan loops = s.impl().loop_plan(&recorder);
  Executor executor(s.impl().executor_settings(), loops.loops());
  std::atomic<bool> stop{false};
  const ExecutorResult r = executor.run(stop);
  recorder.close();
  EXPECT_FALSE(recorder.failed()) << recorder.error();
  EXPECT_EQ(recorder.dropped(), 0u);
  EXPECT_EQ(recorder.written(), r.statistics.cycles * s.impl().devices.size());
  const auto csv = test::recording_csv(file);
  return csv.at("a") + csv.at("b");
}

TEST(Executor, LockstepRunsTheDurationThenTheRamp) {
  auto s = test::build_test_session(lockstep_yaml(0.5, test::mass_spring_device_yaml("a")));
  const LoopPlan loops = s.impl().loop_plan();
  Executor executor(s.impl().executor_settings(), loops.loops());
  std::atomic<bool> stop{false};
  const ExecutorResult r = executor.run(stop);
  EXPECT_EQ(r.statistics.cycles, 1000u + 200u);  // 0.5 s + 0.1 s ramp at 2 kHz
  EXPECT_EQ(r.periods, r.statistics.cycles);
  EXPECT_EQ(r.statistics.compute_time.count(), r.statistics.cycles);
  EXPECT_EQ(r.statistics.overruns, 0u);
  EXPECT_EQ(r.statistics.skipped_cycles, 0u);
  EXPECT_EQ(r.statistics.wakeup_latency.max_ns(), 0);  // a virtual clock wakes exactly on time
  EXPECT_NEAR(r.loop_time_s, 1199 * 0.0005, 1e-12);
  EXPECT_FALSE(r.stop_requested);
  EXPECT_EQ(s.impl().devices[0]->command().torque_nm[0], 0.0);  // the ramp ends at zero torque
}

TEST(Executor, LockstepIsBitIdenticalAcrossRunsAndDependsOnTheSeed) {
  const std::string devices = test::mass_spring_device_yaml("a", ", position_noise_m: 1.0e-4") +
                              test::mass_spring_device_yaml("b", ", position_noise_m: 1.0e-4");
  const std::string first = run_recorded(lockstep_yaml(1.0, devices, 7), "first.h5");
  const std::string second = run_recorded(lockstep_yaml(1.0, devices, 7), "second.h5");
  const std::string other_seed = run_recorded(lockstep_yaml(1.0, devices, 8), "other.h5");
  EXPECT_GT(first.size(), 1'000'000u);
  EXPECT_TRUE(first == second) << "two lockstep runs of the same session differ";
  EXPECT_FALSE(first == other_seed) << "the seed has no effect: the determinism check would prove nothing";
}

TEST(Executor, StopRequestTakesEveryDeviceThroughItsSafeModeThenEnds) {
  // No duration: runs until stopped (SIGINT/SIGTERM in the server). The monitor (caller's thread) requests the
  // stop; every device then damps for safe_damping_s (0.5 s = 1000 cycles) and the loop ends at zero torque.
  auto s = test::build_test_session(
      lockstep_yaml(0.0, test::mass_spring_device_yaml("a") + test::mass_spring_device_yaml("b")));
  const auto file = test::write_temp_file("stop.h5", "");
  Recorder recorder(file, recording_header(s.impl().config, s.impl().device_pointers()), true);
  const LoopPlan loops = s.impl().loop_plan(&recorder);
  Executor executor(s.impl().executor_settings(), loops.loops());
  std::atomic<bool> stop{false};
  const ExecutorResult r = executor.run(stop, [&] {
    if (executor.live().cycles.load() >= 400) stop.store(true);  // once the devices move
  });
  recorder.close();
  EXPECT_TRUE(r.stop_requested);
  ASSERT_GE(r.statistics.cycles, 1401u);
  for (const auto& d : s.impl().devices) {
    EXPECT_EQ(d->status().fault(), DeviceFault::none);  // a requested stop is not a fault
    EXPECT_TRUE(d->status().at_rest());
    EXPECT_EQ(d->command().torque_nm[0], 0.0);
  }
  // Device a's velocity and torque columns: over the last 1001 cycles - after the 20 ms (40 cycles) in which
  // the last torque fades out - the torque only opposes the motion (damping), and the last one is zero.
  const std::string a = test::recording_csv(file).at("a");
  const std::vector<double> velocity = test::recording_column(a, "joints.velocity.");
  const std::vector<double> torque = test::recording_column(a, "joints.torque_command.");
  ASSERT_EQ(torque.size(), r.statistics.cycles);
  int damping = 0;
  for (std::size_t k = torque.size() - 1001 + 40; k < torque.size(); ++k) {
    ASSERT_LE(torque[k] * velocity[k], 0.0) << "cycle " << k;
    if (torque[k] != 0.0) ++damping;
  }
  EXPECT_GT(damping, 500);
  EXPECT_EQ(torque.back(), 0.0);
}

TEST(Executor, RealtimeLoopAccountsForEveryPeriod) {
  auto s = test::build_test_session(
      "server: {clock: realtime, rate_hz: 2000, duration_s: 0.1, shutdown_ramp_s: 0.01}\ndevices:\n" +
      test::mass_spring_device_yaml("a"));
  const LoopPlan loops = s.impl().loop_plan();
  Executor executor(s.impl().executor_settings(), loops.loops());
  std::atomic<bool> stop{false};
  const ExecutorResult r = executor.run(stop);
  // Every period is either run or counted as skipped, however loaded the machine is; the session lasts its
  // duration plus the ramp on the clock (a skip may overshoot the last period of the ramp).
  EXPECT_EQ(r.statistics.cycles + r.statistics.skipped_cycles, r.periods);
  EXPECT_GE(r.periods, 200u + 20u);
  EXPECT_LE(r.periods, 200u + 20u + r.statistics.skipped_cycles);
  EXPECT_EQ(r.statistics.wakeup_latency.count(), r.statistics.cycles);
  EXPECT_GE(r.wall_time_s, 0.1);
}

}  // namespace
}  // namespace hapticd::server
