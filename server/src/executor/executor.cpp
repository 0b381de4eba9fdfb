#include "executor/executor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "executor/realtime_setup.hpp"
#include "hapticd/demand.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

Executor::Executor(ExecutorSettings settings, std::vector<DeviceSession*> sessions, Recorder* recorder,
                   std::vector<GroupStage*> stages)
    : settings_(settings),
      group_(std::move(sessions), recorder, std::move(stages)),
      period_ns_(static_cast<std::int64_t>(std::llround(1e9 / settings.rate_hz))) {
  HAPTICD_DEMAND(period_ns_ > 0);  // the rate is validated with the session file (server.rate_hz)
}

void Executor::loop(LoopClock& clock, const std::atomic<bool>& stop_requested, ExecutorResult& result) noexcept {
  CycleStatistics& stats = result.statistics;
  const std::uint64_t run_cycles =
      settings_.duration_s > 0.0 ? static_cast<std::uint64_t>(std::llround(settings_.duration_s * settings_.rate_hz))
                                 : 0;
  const auto ramp_cycles = std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::llround(settings_.shutdown_ramp_s * settings_.rate_hz)));

  const std::int64_t start_ns = clock.now_ns();
  std::int64_t deadline_ns = start_ns;  // cycle 0 runs at once
  std::uint64_t ramp_start = 0;
  bool ramping = false;   // the duration has passed: torques ramp to zero
  bool stopping = false;  // stop requested (SIGINT/SIGTERM): every device goes through its safe mode
  std::uint32_t consecutive_overruns = 0;
  const auto window_cycles = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(settings_.rate_hz)));
  std::int64_t window_latency_ns = 0, window_compute_ns = 0;

  for (;;) {
    clock.sleep_until(deadline_ns);
    const auto index = static_cast<std::uint64_t>((deadline_ns - start_ns) / period_ns_);
    const std::int64_t wake_ns = clock.now_ns();
    const std::int64_t compute_start_ns = monotonic_now_ns();

    if (!ramping && !stopping && stop_requested.load(std::memory_order_relaxed)) {
      stopping = true;
      result.stop_requested = true;
      for (DeviceSession* s : group_.devices()) s->request_safe_stop();
    }
    if (!ramping && !stopping && run_cycles > 0 && index >= run_cycles) {
      ramping = true;
      ramp_start = index;
    }
    // Linear ramp from 1 to 0 over ramp_cycles; the last cycle of the ramp commands exactly zero.
    const double scale =
        ramping ? std::max(0.0, 1.0 - static_cast<double>(index - ramp_start + 1) / static_cast<double>(ramp_cycles))
                : 1.0;

    // One cycle in phases, each for every device before the next (docs/architecture.md, "One cycle").
    group_.run_cycle(CycleTime{deadline_ns - start_ns, period_ns_, index}, scale, consecutive_overruns,
                     wake_ns - deadline_ns);

    const std::int64_t compute_end_ns = monotonic_now_ns();
    if (listener_ != nullptr) listener_->after_cycle(index, clock.is_virtual());
    const std::int64_t next_deadline_ns = deadline_ns + period_ns_;
    const bool overrun = !clock.is_virtual() && clock.now_ns() > next_deadline_ns;
    consecutive_overruns = overrun ? consecutive_overruns + 1 : 0;
    stats.record(wake_ns - deadline_ns, compute_end_ns - compute_start_ns, overrun);
    window_latency_ns = std::max(window_latency_ns, wake_ns - deadline_ns);
    window_compute_ns = std::max(window_compute_ns, compute_end_ns - compute_start_ns);
    live_.cycles.store(stats.cycles, std::memory_order_relaxed);
    live_.overruns.store(stats.overruns, std::memory_order_relaxed);
    if ((index + 1) % window_cycles == 0) {
      live_.window_latency_max_ns.store(window_latency_ns, std::memory_order_relaxed);
      live_.window_compute_max_ns.store(window_compute_ns, std::memory_order_relaxed);
      window_latency_ns = window_compute_ns = 0;
    }

    const bool stopped = stopping && group_.at_rest();
    if ((ramping && index - ramp_start + 1 >= ramp_cycles) || stopped) {
      result.periods = index + 1;
      break;
    }

    deadline_ns = next_deadline_ns;
    if (overrun) {
      // Behind by more than a period: keep the absolute schedule but skip the deadlines already missed.
      const std::int64_t behind_ns = clock.now_ns() - deadline_ns;
      if (behind_ns > period_ns_) {
        const std::int64_t missed = behind_ns / period_ns_;
        deadline_ns += missed * period_ns_;
        stats.skipped_cycles += static_cast<std::uint64_t>(missed);
      }
    }
  }
  result.loop_time_s = static_cast<double>(clock.now_ns() - start_ns) * 1e-9;
}

ExecutorResult Executor::run(const std::atomic<bool>& stop_requested, const std::function<void()>& monitor) {
  ExecutorResult result;
  const std::vector<DeviceSession*>& devices = group_.devices();
  if (!settings_.lockstep && settings_.lock_memory)
    if (std::string w = lock_process_memory(); !w.empty()) result.warnings.push_back(std::move(w));

  // The loop thread exists before any device is powered: a thread that cannot be created (no memory) ends the
  // start with an error while every drive is still off.
  std::atomic<bool> go{false};
  std::atomic<bool> cancelled{false};
  std::atomic<bool> done{false};
  std::int64_t wall_start_ns = 0;
  std::thread thread([&] {
    while (!go.load(std::memory_order_acquire)) std::this_thread::yield();
    if (cancelled.load(std::memory_order_acquire)) return;
    if (!settings_.lockstep) minimise_timer_slack();
    if (!settings_.lockstep && settings_.lock_memory) prefault_stack();
    if (settings_.lockstep) {
      VirtualClock clock;
      loop(clock, stop_requested, result);
    } else {
      MonotonicClock clock;
      loop(clock, stop_requested, result);
    }
    done.store(true, std::memory_order_release);
  });
  try {
    if (!settings_.lockstep) {
      auto warnings = make_thread_realtime(thread, settings_.realtime_priority, settings_.cpu);
      result.warnings.insert(result.warnings.end(), warnings.begin(), warnings.end());
    }
  } catch (...) {
    // The loop never runs and no device was powered.
    cancelled.store(true, std::memory_order_release);
    go.store(true, std::memory_order_release);
    thread.join();
    throw;
  }
  // A device that cannot be enabled or homed is held in its safe state by its session; the others run.
  for (DeviceSession* d : devices) d->activate();
  wall_start_ns = monotonic_now_ns();
  go.store(true, std::memory_order_release);

  while (!done.load(std::memory_order_acquire)) {
    if (monitor) monitor();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  thread.join();
  if (monitor) monitor();
  result.wall_time_s = static_cast<double>(monotonic_now_ns() - wall_start_ns) * 1e-9;

  for (DeviceSession* s : devices) {
    s->deactivate();
    if (!s->disable_error().empty())
      result.warnings.push_back("device '" + s->name() + "': " + s->disable_error() + " (its drives may still be on)");
  }
  return result;
}

}  // namespace hapticd::server
