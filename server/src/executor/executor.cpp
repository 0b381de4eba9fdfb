#include "executor/executor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "executor/realtime_setup.hpp"
#include "hapticd/demand.hpp"

namespace hapticd::server {

Executor::Executor(ExecutorSettings settings, const std::vector<ExecutorLoop>& loops)
    : settings_(settings), period_ns_(static_cast<std::int64_t>(std::llround(1e9 / settings.rate_hz))) {
  HAPTICD_DEMAND(period_ns_ > 0);  // the rate is validated with the session file (server.rate_hz)
  HAPTICD_DEMAND(!loops.empty());
  for (const ExecutorLoop& l : loops) {
    HAPTICD_DEMAND(l.work != nullptr);
    loops_.push_back(std::make_unique<Loop>(l.name, l.cpu, *l.work, l.device_clock));
  }
}

void Executor::loop(Loop& loop, LoopClock& clock, const std::atomic<bool>& stop_requested,
                    LoopResult& result) noexcept {
  CycleStatistics& stats = result.statistics;
  LoopWork& work = loop.work;
  LiveLoopStatistics& live = loop.live;
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

  std::uint64_t index = 0;
  for (bool first = true;; first = false) {
    // Due at the deadline; on a device's clock, at the device's tick (its time is the cycle's).
    std::uint64_t missed = 0;
    deadline_ns = clock.wait_for_cycle(deadline_ns, missed);
    if (clock.follows_device()) {
      // Ticks the device made before the loop's first cycle are not periods of the run (CI saw one: counted as
      // skipped, cycles + skipped came to one more than the periods).
      if (first) missed = 0;
      index = first ? 0 : index + 1 + missed;
      stats.skipped_cycles += missed;
    } else {
      index = static_cast<std::uint64_t>((deadline_ns - start_ns) / period_ns_);
    }
    const std::int64_t wake_ns = clock.now_ns();
    const std::int64_t compute_start_ns = monotonic_now_ns();

    if (!ramping && !stopping && stop_requested.load(std::memory_order_relaxed)) {
      stopping = true;
      result.stop_requested = true;
      work.request_safe_stop();
    }
    if (!ramping && !stopping && run_cycles > 0 && index >= run_cycles) {
      ramping = true;
      ramp_start = index;
    }
    // Linear ramp from 1 to 0 over ramp_cycles; the last cycle of the ramp commands exactly zero.
    const double scale =
        ramping ? std::max(0.0, 1.0 - static_cast<double>(index - ramp_start + 1) / static_cast<double>(ramp_cycles))
                : 1.0;

    // One cycle of the loop's work (its devices in phases: docs/architecture.md, "One cycle").
    work.run_cycle(CycleTime{deadline_ns - start_ns, period_ns_, index}, scale, consecutive_overruns,
                   wake_ns - deadline_ns);

    const std::int64_t compute_end_ns = monotonic_now_ns();
    if (listener_ != nullptr) listener_->after_cycle(index, clock.is_virtual());
    const std::int64_t next_deadline_ns = deadline_ns + period_ns_;
    const bool overrun = !clock.is_virtual() && clock.now_ns() > next_deadline_ns;
    consecutive_overruns = overrun ? consecutive_overruns + 1 : 0;
    stats.record(wake_ns - deadline_ns, compute_end_ns - compute_start_ns, overrun);
    window_latency_ns = std::max(window_latency_ns, wake_ns - deadline_ns);
    window_compute_ns = std::max(window_compute_ns, compute_end_ns - compute_start_ns);
    live.cycles.store(stats.cycles, std::memory_order_relaxed);
    live.overruns.store(stats.overruns, std::memory_order_relaxed);
    if ((index + 1) % window_cycles == 0) {
      live.window_latency_max_ns.store(window_latency_ns, std::memory_order_relaxed);
      live.window_compute_max_ns.store(window_compute_ns, std::memory_order_relaxed);
      window_latency_ns = window_compute_ns = 0;
    }

    const bool stopped = stopping && work.at_rest();
    if ((ramping && index - ramp_start + 1 >= ramp_cycles) || stopped) {
      result.periods = index + 1;
      break;
    }

    deadline_ns = next_deadline_ns;
    if (overrun && !clock.follows_device()) {  // a device's ticks say themselves which periods went by
      // Behind by more than a period: keep the absolute schedule but skip the deadlines already missed.
      const std::int64_t behind_ns = clock.now_ns() - deadline_ns;
      if (behind_ns > period_ns_) {
        const std::int64_t passed = behind_ns / period_ns_;
        deadline_ns += passed * period_ns_;
        stats.skipped_cycles += static_cast<std::uint64_t>(passed);
      }
    }
  }
  result.loop_time_s = static_cast<double>(clock.now_ns() - start_ns) * 1e-9;
}

namespace {
std::atomic<int> g_loops_running{0};
}  // namespace

int Executor::loops_running() noexcept { return g_loops_running.load(std::memory_order_acquire); }

ExecutorResult Executor::run(const std::atomic<bool>& stop_requested, const std::function<void()>& monitor) {
  ExecutorResult result;
  if (!settings_.lockstep && settings_.lock_memory)
    if (std::string w = lock_process_memory(); !w.empty()) result.warnings.push_back(std::move(w));
  CpuLatencyLimit cpu_latency;  // held until the loops have ended
  if (!settings_.lockstep && settings_.cpu_dma_latency_us >= 0)
    if (std::string w = cpu_latency.hold(settings_.cpu_dma_latency_us); !w.empty())
      result.warnings.push_back(std::move(w));
  result.loops.resize(loops_.size());
  for (std::size_t k = 0; k < loops_.size(); ++k) {
    result.loops[k].name = loops_[k]->name;
    result.loops[k].cpu = settings_.lockstep ? -1 : loops_[k]->cpu;
    result.loops[k].devices = loops_[k]->work.device_names();
  }

  // The loop threads exist before any device is powered: a thread that cannot be created (no memory) ends the
  // start with an error while every drive is still off.
  std::atomic<bool> go{false};
  std::atomic<bool> cancelled{false};
  std::atomic<std::size_t> running{loops_.size()};
  std::int64_t wall_start_ns = 0;
  std::vector<std::thread> threads;
  const auto join_all = [&] {
    for (std::thread& t : threads)
      if (t.joinable()) t.join();
  };
  try {
    for (std::size_t k = 0; k < loops_.size(); ++k) {
      threads.emplace_back([&, k] {
        // Asleep until then (a futex, not a spin: SCHED_FIFO loop threads spinning on every CPU would starve the
        // thread that powers the devices, and the kernel's real-time throttling would then stall the loops).
        go.wait(false, std::memory_order_acquire);
        if (cancelled.load(std::memory_order_acquire)) return;
        // A broken invariant here aborts at once: nothing else can take this loop's devices to their safe mode.
        internal::abort_on_demand_failure_in_this_thread();
        g_loops_running.fetch_add(1, std::memory_order_acq_rel);
        // "hapticd-loop", or "loop-<group>" for a group's own loop: found by name in ps, top and traces.
        name_this_thread(loops_[k]->name == "session" ? "hapticd-loop" : "loop-" + loops_[k]->name);
        if (!settings_.lockstep) minimise_timer_slack();
        if (!settings_.lockstep && settings_.lock_memory) prefault_stack();
        if (settings_.lockstep) {
          VirtualClock clock;
          loop(*loops_[k], clock, stop_requested, result.loops[k]);
        } else if (loops_[k]->device_clock != nullptr) {
          DeviceTickClock clock(*loops_[k]->device_clock, settings_.device_clock_stall_ns,
                                settings_.device_clock_first_tick_ns);
          loop(*loops_[k], clock, stop_requested, result.loops[k]);
        } else {
          MonotonicClock clock;
          loop(*loops_[k], clock, stop_requested, result.loops[k]);
        }
        g_loops_running.fetch_sub(1, std::memory_order_acq_rel);
        running.fetch_sub(1, std::memory_order_release);
      });
      if (settings_.lockstep) continue;
      for (std::string& w : make_thread_realtime(threads.back(), settings_.realtime_priority, loops_[k]->cpu))
        result.warnings.push_back(loops_.size() > 1 ? "loop '" + loops_[k]->name + "': " + w : std::move(w));
    }
  } catch (...) {
    // No loop runs and no device was powered.
    cancelled.store(true, std::memory_order_release);
    go.store(true, std::memory_order_release);
    go.notify_all();
    join_all();
    throw;
  }
  // A device that cannot be enabled or homed is held in its safe state by its session; the others run.
  for (const auto& l : loops_) l->work.activate();
  wall_start_ns = monotonic_now_ns();
  go.store(true, std::memory_order_release);
  go.notify_all();

  while (running.load(std::memory_order_acquire) > 0) {
    if (monitor) monitor();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  join_all();
  if (monitor) monitor();
  result.wall_time_s = static_cast<double>(monotonic_now_ns() - wall_start_ns) * 1e-9;

  for (const LoopResult& l : result.loops) {
    CycleStatistics& all = result.statistics;
    all.wakeup_latency.merge(l.statistics.wakeup_latency);
    all.compute_time.merge(l.statistics.compute_time);
    all.cycles += l.statistics.cycles;
    all.overruns += l.statistics.overruns;
    all.skipped_cycles += l.statistics.skipped_cycles;
    all.max_consecutive_overruns = std::max(all.max_consecutive_overruns, l.statistics.max_consecutive_overruns);
    result.periods = std::max(result.periods, l.periods);
    result.loop_time_s = std::max(result.loop_time_s, l.loop_time_s);
    result.stop_requested = result.stop_requested || l.stop_requested;
  }
  for (const auto& l : loops_) l->work.deactivate(result.warnings, result.plugin_errors);
  return result;
}

}  // namespace hapticd::server
