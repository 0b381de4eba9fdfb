#pragma once
// The fixed-rate loops. Each runs on a thread of its own (SCHED_FIFO and locked memory when permitted), sleeps
// to absolute deadlines on its clock, runs its LoopWork each cycle (executor/loop_work.hpp: what it drives is not
// the executor's business) and keeps timing statistics. Every loop runs at the same rate on the same schedule,
// each on the CPU it is given (in lockstep the caller gives one loop, cycle/LoopPlan: the virtual clock has no
// CPUs to spread over, and one thread keeps runs repeatable). When the
// duration is reached each loop ramps its torques linearly to zero over the shutdown ramp, then stops; when a stop
// is requested (SIGINT/SIGTERM) the work takes an emergency stop - its safe modes, damping then zero torque - and a
// loop stops once its work is at rest. Each cycle tells the work the current run of consecutive overruns of its
// loop (the devices' watchdog). A loop may take its clock from a device whose SDK owns the servo loop
// (`server.clock: device`, executor/loop_clock.hpp): one cycle per tick, the same statistics and watchdogs.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "executor/cycle_statistics.hpp"
#include "executor/loop_clock.hpp"
#include "executor/loop_work.hpp"

namespace hapticd::server {

// Told by the loop thread after every cycle, once all devices have run (the DDS bridge: wake the publisher;
// in lockstep, wait for the engine's answer). Real-time safe by contract in realtime mode.
class CycleListener {
 public:
  virtual ~CycleListener() = default;
  virtual void after_cycle(std::uint64_t index, bool lockstep) noexcept = 0;
};

struct ExecutorSettings {
  double rate_hz = 2000.0;
  bool lockstep = false;
  double duration_s = 0.0;  // 0: until stop is requested
  double shutdown_ramp_s = 0.2;
  int realtime_priority = 0;
  bool lock_memory = false;
  int cpu = -1;
  int cpu_dma_latency_us = -1;  // held while running (realtime only); -1: left alone
  // A loop on a device's clock (ExecutorLoop::device_clock): a tick this late is a stall (the cycle runs then, and
  // the loop runs on its own clock until the device ticks again); the first tick may take longer.
  std::int64_t device_clock_stall_ns = 20'000'000;
  std::int64_t device_clock_first_tick_ns = 1'000'000'000;
};

// One loop: its name ("session", or a group's), its CPU (-1: not pinned), what it runs (outlives the executor)
// and, for `server.clock: device`, the clock of the device it runs on (null: its own; ignored in lockstep).
struct ExecutorLoop {
  std::string name;
  int cpu = -1;
  LoopWork* work = nullptr;
  DeviceClock* device_clock = nullptr;
};

// One loop's figures.
struct LoopResult {
  std::string name;  // "session", or the group's
  int cpu = -1;
  std::vector<std::string> devices;
  CycleStatistics statistics;
  std::uint64_t periods = 0;
  double loop_time_s = 0.0;
  bool stop_requested = false;
};

struct ExecutorResult {
  CycleStatistics statistics;  // every loop's cycles together
  std::vector<LoopResult> loops;
  std::vector<std::string> warnings;  // real-time set-up that was not permitted; a device not disabled cleanly
  // What plugins threw as they were deactivated at the end (those of schemes left during the run: the monitor
  // logged them). The devices were disabled all the same.
  std::vector<std::string> plugin_errors;
  bool stop_requested = false;  // ended by request rather than by duration
  std::uint64_t periods = 0;    // periods elapsed on the loop clock: cycles run + skipped (the longest loop)
  double loop_time_s = 0.0;     // time on the loop clock (virtual in lockstep; the longest loop)
  double wall_time_s = 0.0;
};

// The loop's health while it runs, readable from any thread (the DDS bridge): counts since the start and the
// worst times of the last complete one-second window. Written by the loop with relaxed atomics.
struct LiveLoopStatistics {
  std::atomic<std::uint64_t> cycles{0};
  std::atomic<std::uint64_t> overruns{0};
  std::atomic<std::int64_t> window_latency_max_ns{0};
  std::atomic<std::int64_t> window_compute_max_ns{0};
};

class Executor {
 public:
  // loops: at least one, each run on a thread of its own.
  Executor(ExecutorSettings settings, const std::vector<ExecutorLoop>& loops);

  // Activates the loops' work, runs the loops until the duration has passed or stop_requested turns true, ramps
  // down and deactivates. While the loops run, the calling thread calls `monitor` every 20 ms (for logging:
  // the loops never log).
  ExecutorResult run(const std::atomic<bool>& stop_requested, const std::function<void()>& monitor = {});
  // Any thread: the loop threads of every executor in the process that have started and not yet ended.
  [[nodiscard]] static int loops_running() noexcept;

  [[nodiscard]] std::int64_t period_ns() const noexcept { return period_ns_; }
  // Before run(). With several loops it is called by each loop's thread (concurrently in real time).
  void set_cycle_listener(CycleListener* listener) noexcept { listener_ = listener; }
  // The live figures of loop k (in the order given).
  [[nodiscard]] const LiveLoopStatistics& live(std::size_t k = 0) const noexcept { return loops_[k]->live; }
  [[nodiscard]] std::size_t loop_count() const noexcept { return loops_.size(); }

 private:
  struct Loop {
    Loop(std::string loop_name, int loop_cpu, LoopWork& loop_work, DeviceClock* clock)
        : name(std::move(loop_name)), cpu(loop_cpu), work(loop_work), device_clock(clock) {}
    std::string name;
    int cpu;
    LoopWork& work;
    DeviceClock* device_clock;
    LiveLoopStatistics live;
  };
  void loop(Loop& loop, LoopClock& clock, const std::atomic<bool>& stop_requested, LoopResult& result) noexcept;

  ExecutorSettings settings_;
  std::vector<std::unique_ptr<Loop>> loops_;
  CycleListener* listener_ = nullptr;
  std::int64_t period_ns_;
};

}  // namespace hapticd::server
