// Loops clocked by a device (`server.clock: device`): the test mass-spring device with a clock of its own (a thread
// that ticks, as OpenHaptics' scheduler calls back) clocks the session's loop. In real time on this machine, short
// and structural: every tick is a cycle or counted as skipped, a device that stops ticking is a loop_stall and the
// loop runs on to a safe stop, a device that ticks again clocks the loop again; the session's mistakes are config
// errors naming server.clock or server.clock_device.
#include <gtest/gtest.h>

#include <atomic>
#include <string>

#include "app/served_session.hpp"
#include "config/config_error.hpp"
#include "executor/executor.hpp"
#include "hapticd/realtime/tick_signal.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

std::string session(const std::string& server, const std::string& a_parameters, const std::string& b_parameters = "") {
  // 100 overruns in a row: the tests run two at a time on two CPUs (the overrun watchdog's own tests are elsewhere).
  const std::string relaxed = "    safety: {max_consecutive_overruns: 100}\n";
  return "server: {rate_hz: 1000, shutdown_ramp_s: 0.05, " + server + "}\ndevices:\n" +
         test::mass_spring_device_yaml("a", a_parameters) + relaxed +
         (b_parameters == "-" ? std::string() : test::mass_spring_device_yaml("b", b_parameters) + relaxed);
}

struct ClockedRun {
  ExecutorResult result;
  std::uint32_t ticks = 0;  // the clock's ticks from enable() to the end of the run
};

ClockedRun run(Session& s) {
  ClockedRun r;
  r.result = test::run_session(s);
  const auto* ticks = dynamic_cast<const realtime::TickSignal*>(s.impl().devices[0]->chain().device->clock());
  if (ticks != nullptr) r.ticks = ticks->ticks();
  return r;
}

std::string config_error(const std::string& yaml) { return test::config_error_of(yaml); }

TEST(DeviceClock, TheLoopRunsOneCycleAtEachTickOfTheDevice) {
  // Device a ticks at 1 kHz; b has no clock and runs in the same loop, on a's ticks. The duration and the ramp are
  // counted in ticks: 300 + 50 periods.
  // A stall watchdog of 0.2 s: this machine's hypervisor stalls a loop by 20 ms now and then (docs/measurements.md).
  const std::string relaxed = "    safety: {max_stall_s: 0.2, max_consecutive_overruns: 100}\n";
  Session s = test::build_test_session(
      "server: {rate_hz: 1000, shutdown_ramp_s: 0.05, clock: device, duration_s: "
      "0.3}\ndevices:\n" +
      test::mass_spring_device_yaml("a", "tick_hz: 1000") + relaxed + test::mass_spring_device_yaml("b") + relaxed);
  const LoopPlan loops = s.impl().loop_plan();
  ASSERT_EQ(loops.loops().size(), 1u);
  EXPECT_EQ(loops.loops()[0].device_clock, s.impl().devices[0]->chain().device->clock());
  const ClockedRun r = run(s);
  EXPECT_GE(r.result.periods, 350u);  // a skip may overshoot the last period of the ramp
  EXPECT_LE(r.result.periods, 350u + r.result.statistics.skipped_cycles);
  EXPECT_EQ(r.result.statistics.cycles + r.result.statistics.skipped_cycles, r.result.periods);
  // The ticks the run saw, and no more than the device made (it ticked from enable() until the end).
  EXPECT_LE(r.result.periods, r.ticks);
  EXPECT_EQ(r.result.statistics.wakeup_latency.count(), r.result.statistics.cycles);  // tick to loop, per cycle
  for (const auto& d : s.impl().devices) EXPECT_EQ(d->status().fault(), DeviceFault::none) << d->name();
  EXPECT_GE(r.result.loop_time_s, 0.349 - 0.001);  // 349 tick periods from the first tick to the last
}

TEST(DeviceClock, ADeviceThatStopsTickingIsALoopStallAndTheLoopRunsOnToRest) {
  // a stops calling after 100 ticks: within its max_stall_s (20 ms) the loop runs that cycle late, every device of
  // the loop faults loop_stall (their loop stalled), and the loop runs on the monotonic clock to the end of the
  // session, so that the safe modes fade and damp (0.5 s): at rest with zero force at the end.
  Session s = test::build_test_session(
      session("clock: device, duration_s: 0.8", "tick_hz: 1000, ticks_before_pause: 100", "position_noise_m: 0"));
  const ClockedRun r = run(s);
  EXPECT_EQ(r.ticks, 100u);
  for (const auto& d : s.impl().devices) {
    EXPECT_EQ(d->status().fault(), DeviceFault::loop_stall) << d->name();
    EXPECT_EQ(d->command().torque_nm[0], 0.0) << d->name();
  }
  EXPECT_GE(r.result.periods, 850u);  // the rest on the loop's own clock (a skip may overshoot the ramp's end)
  EXPECT_LE(r.result.periods, 850u + r.result.statistics.skipped_cycles);
  EXPECT_GE(r.result.statistics.wakeup_latency.max_ns(), 20'000'000);  // the stalled cycle woke that late
}

TEST(DeviceClock, ADeviceThatTicksAgainClocksTheLoopAgain) {
  // A pause of 60 ms after 100 ticks: one stall (the devices keep their latched fault), then the loop follows the
  // ticks again: the run ends on a tick, not on the loop's own clock.
  Session s = test::build_test_session(
      session("clock: device, duration_s: 0.5", "tick_hz: 1000, ticks_before_pause: 100, tick_pause_s: 0.06", "-"));
  const ClockedRun r = run(s);
  EXPECT_EQ(s.impl().devices[0]->status().fault(), DeviceFault::loop_stall);
  EXPECT_GE(r.result.periods, 550u);  // a skip may overshoot the last period of the ramp
  EXPECT_LE(r.result.periods, 550u + r.result.statistics.skipped_cycles);
  EXPECT_GT(r.ticks, 400u);  // most of the run came from the device's ticks again
  EXPECT_EQ(r.result.statistics.cycles + r.result.statistics.skipped_cycles, r.result.periods);
}

TEST(DeviceClock, TheSessionsMistakesAreConfigErrorsNamingTheKey) {
  std::string e = config_error(session("clock: device", "", "-"));
  EXPECT_NE(e.find(": server.clock: "), std::string::npos) << e;
  EXPECT_NE(e.find("no device of the session has a clock of its own"), std::string::npos) << e;
  e = config_error(session("clock: device", "tick_hz: 1000", "tick_hz: 1000"));
  EXPECT_NE(e.find("'a' and 'b' can both clock the session"), std::string::npos) << e;
  e = config_error(session("clock: device, clock_device: b", "tick_hz: 1000"));
  EXPECT_NE(e.find(": server.clock_device: "), std::string::npos) << e;
  EXPECT_NE(e.find("device 'b' (plugin 'test_mass_spring') has no clock of its own"), std::string::npos) << e;
  e = config_error(session("clock: device, clock_device: c", "tick_hz: 1000"));
  EXPECT_NE(e.find("no device 'c' runs in this session"), std::string::npos) << e;
  e = config_error(session("clock: realtime, clock_device: a", "tick_hz: 1000"));
  EXPECT_NE(e.find(": server.clock_device: "), std::string::npos) << e;
  e = config_error("server: {rate_hz: 1000, clock: device}\ndevices:\n" +
                   test::mass_spring_device_yaml("a", "tick_hz: 1000") + "    safety: {max_stall_s: off}\n");
  EXPECT_NE(e.find("its stall watchdog must be on"), std::string::npos) << e;
  // The line of server.clock is in the message (file:line: key: ...).
  e = config_error(session("clock: device", "", "-"));
  EXPECT_NE(e.find(":1: server.clock: "), std::string::npos) << e;
}

TEST(DeviceClock, InLockstepTheVirtualClockRunsTheLoop) {
  // A lockstep run stays repeatable: a device's clock is ignored there (and clock: lockstep needs none).
  Session s = test::build_test_session(session("clock: lockstep, duration_s: 0.1", "tick_hz: 1000", "-"));
  const LoopPlan loops = s.impl().loop_plan();
  EXPECT_EQ(loops.loops()[0].device_clock, nullptr);
}

}  // namespace
}  // namespace hapticd::server
