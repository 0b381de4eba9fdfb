#pragma once
// The fixed-rate loop. It runs on a thread of its own (SCHED_FIFO and locked memory when permitted), sleeps
// to absolute deadlines on its clock, runs every device session of the group each cycle (all devices see the
// same instant), hands records to the recorder, and keeps timing statistics. When the duration is reached it
// ramps every device's torque linearly to zero over the shutdown ramp, then stops; when a stop is requested
// (SIGINT/SIGTERM) every device takes an emergency stop - its safe mode, damping then zero torque - and the loop
// stops once all of them are at zero torque. Each cycle tells the devices the current run of consecutive
// overruns (their watchdog).
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "executor/cycle_statistics.hpp"
#include "executor/device_group.hpp"
#include "executor/loop_clock.hpp"

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
};

struct ExecutorResult {
  CycleStatistics statistics;
  std::vector<std::string> warnings;  // real-time set-up that was not permitted
  bool stop_requested = false;        // ended by request rather than by duration
  std::uint64_t periods = 0;          // periods elapsed on the loop clock: cycles run + skipped
  double loop_time_s = 0.0;           // time on the loop clock (virtual in lockstep)
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
  // stages: the group stages of the device groups among the sessions (phase (b) of each cycle).
  Executor(ExecutorSettings settings, std::vector<DeviceSession*> sessions, Recorder* recorder,
           std::vector<GroupStage*> stages = {});

  // Activates the sessions, runs the loop until the duration has passed or stop_requested turns true, ramps
  // down and deactivates. While the loop runs, the calling thread calls `monitor` every 20 ms (for logging:
  // the loop never logs).
  ExecutorResult run(const std::atomic<bool>& stop_requested, const std::function<void()>& monitor = {});

  [[nodiscard]] std::int64_t period_ns() const noexcept { return period_ns_; }
  // Before run().
  void set_cycle_listener(CycleListener* listener) noexcept { listener_ = listener; }
  [[nodiscard]] const LiveLoopStatistics& live() const noexcept { return live_; }

 private:
  void loop(LoopClock& clock, const std::atomic<bool>& stop_requested, ExecutorResult& result) noexcept;

  ExecutorSettings settings_;
  DeviceGroup group_;  // the devices, and their cycle
  CycleListener* listener_ = nullptr;
  LiveLoopStatistics live_;
  std::int64_t period_ns_;
};

}  // namespace hapticd::server
