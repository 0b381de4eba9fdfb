#pragma once
// The fixed-rate loops. Each runs on a thread of its own (SCHED_FIFO and locked memory when permitted), sleeps
// to absolute deadlines on its clock, runs its devices each cycle in phases (all devices of a loop see the same
// instant), hands records to the recorder, and keeps timing statistics. The session's loop drives every device
// not in a group with a loop of its own (`groups[i].loop`); each such group runs on a loop thread of its own,
// pinned to its CPU, at the same rate and on the same schedule. In lockstep every loop runs on one thread (the
// virtual clock has no CPUs to spread over, and one thread keeps runs repeatable). When the duration is reached
// each loop ramps its devices' torques linearly to zero over the shutdown ramp, then stops; when a stop is
// requested (SIGINT/SIGTERM) every device takes an emergency stop - its safe mode, damping then zero torque - and
// a loop stops once all its devices are at zero torque. Each cycle tells the devices the current run of
// consecutive overruns of their loop (their watchdog).
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "executor/cycle_statistics.hpp"
#include "executor/loop_clock.hpp"
#include "executor/loop_cycle.hpp"

namespace hapticd::server {

class DeviceSession;
class Recorder;

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
};

// A group whose devices run on a loop thread of their own (`groups[i].loop`).
struct SeparateLoop {
  std::string name;  // the group's
  std::vector<DeviceSession*> devices;
  int cpu = -1;  // -1: not pinned
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
  // sessions: every device, in the session's order (their numbers in the recording); stages: the device groups'
  // stages (phase (b) of each cycle), each run by the loop that holds its devices; separate: the groups with a
  // loop of their own (ignored in lockstep). The recorder, if any, has a ring for every loop.
  Executor(ExecutorSettings settings, std::vector<DeviceSession*> sessions, Recorder* recorder,
           std::vector<GroupStage*> stages = {}, const std::vector<SeparateLoop>& separate = {});

  // Activates the sessions, runs the loop until the duration has passed or stop_requested turns true, ramps
  // down and deactivates. While the loop runs, the calling thread calls `monitor` every 20 ms (for logging:
  // the loop never logs).
  ExecutorResult run(const std::atomic<bool>& stop_requested, const std::function<void()>& monitor = {});
  // Any thread: the loop threads of every executor in the process that have started and not yet ended.
  [[nodiscard]] static int loops_running() noexcept;

  [[nodiscard]] std::int64_t period_ns() const noexcept { return period_ns_; }
  // Before run(). With several loops it is called by each loop's thread (concurrently in real time).
  void set_cycle_listener(CycleListener* listener) noexcept { listener_ = listener; }
  // The live figures of the first loop, and of the loop that drives `device`.
  [[nodiscard]] const LiveLoopStatistics& live() const noexcept { return loops_.front()->live; }
  [[nodiscard]] const LiveLoopStatistics& live_of(const DeviceSession* device) const noexcept;
  [[nodiscard]] std::size_t loop_count() const noexcept { return loops_.size(); }

 private:
  struct Loop {
    Loop(std::string loop_name, int loop_cpu, LoopCycle loop_cycle)
        : name(std::move(loop_name)), cpu(loop_cpu), cycle(std::move(loop_cycle)) {}
    std::string name;
    int cpu;
    LoopCycle cycle;  // the devices, and their cycle
    LiveLoopStatistics live;
  };
  void loop(Loop& loop, LoopClock& clock, const std::atomic<bool>& stop_requested, LoopResult& result) noexcept;

  ExecutorSettings settings_;
  std::vector<DeviceSession*> sessions_;
  std::vector<std::unique_ptr<Loop>> loops_;  // the session's first (when it has devices), then the groups'
  CycleListener* listener_ = nullptr;
  std::int64_t period_ns_;
};

}  // namespace hapticd::server
