#include "gate/round_trip_probe.hpp"

#include <algorithm>
#include <numeric>

namespace hapticd::server {

std::uint64_t RoundTripStatistics::applied() const noexcept {
  return std::accumulate(applied_after_cycles.begin(), applied_after_cycles.end(), std::uint64_t{0});
}

void RoundTripProbe::state_written(std::uint64_t state_serial, std::uint64_t cycle, std::int64_t now_ns) noexcept {
  StateSlot& s = states_[state_serial % kSlots];
  s.serial.store(0, std::memory_order_relaxed);  // invalid while it changes (a sequence lock)
  std::atomic_thread_fence(std::memory_order_release);
  s.cycle.store(cycle, std::memory_order_relaxed);
  s.written_ns.store(now_ns, std::memory_order_relaxed);
  s.serial.store(state_serial, std::memory_order_release);
}

std::int64_t RoundTripProbe::command_accepted(std::uint64_t command_serial, std::uint64_t state_serial) noexcept {
  if (state_serial == 0) return 0;
  const StateSlot& s = states_[state_serial % kSlots];
  if (s.serial.load(std::memory_order_acquire) != state_serial) return 0;  // too old: its slot was reused
  const std::uint64_t cycle = s.cycle.load(std::memory_order_relaxed);
  const std::int64_t written = s.written_ns.load(std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_acquire);
  if (s.serial.load(std::memory_order_relaxed) != state_serial) return 0;  // reused while we read it
  CommandSlot& c = commands_[command_serial % kSlots];
  c.serial.store(0, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  c.state_cycle.store(cycle, std::memory_order_relaxed);
  c.serial.store(command_serial, std::memory_order_release);
  return written;
}

void RoundTripProbe::command_handed_over(std::int64_t state_written_ns, std::int64_t now_ns) noexcept {
  if (state_written_ns == 0) return;
  std::lock_guard lock(mutex_);
  round_trips_.record(now_ns - state_written_ns);
}

void RoundTripProbe::command_applied(std::uint64_t command_serial, std::uint64_t cycle) noexcept {
  if (command_serial == last_applied_) return;
  last_applied_ = command_serial;
  const CommandSlot& c = commands_[command_serial % kSlots];
  if (c.serial.load(std::memory_order_acquire) != command_serial) return;
  const std::uint64_t state_cycle = c.state_cycle.load(std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_acquire);
  if (c.serial.load(std::memory_order_relaxed) != command_serial || cycle < state_cycle) return;
  const std::size_t bin = std::min<std::uint64_t>(cycle - state_cycle, RoundTripStatistics::kAppliedBins - 1);
  applied_[bin].fetch_add(1, std::memory_order_relaxed);
}

void RoundTripProbe::merge_into(LatencyHistogram& round_trips, RoundTripStatistics& counts) const {
  {
    std::lock_guard lock(mutex_);
    round_trips.merge(round_trips_);
  }
  for (std::size_t i = 0; i < applied_.size(); ++i)
    counts.applied_after_cycles[i] += applied_[i].load(std::memory_order_relaxed);
}

RoundTripStatistics summarise_round_trips(const LatencyHistogram& round_trips, RoundTripStatistics counts) {
  counts.count = round_trips.count();
  counts.p50_us = static_cast<double>(round_trips.quantile_ns(0.5)) * 1e-3;
  counts.p99_us = static_cast<double>(round_trips.quantile_ns(0.99)) * 1e-3;
  counts.max_us = static_cast<double>(round_trips.max_ns()) * 1e-3;
  return counts;
}

RoundTripStatistics RoundTripProbe::statistics() const {
  LatencyHistogram round_trips;
  RoundTripStatistics counts;
  merge_into(round_trips, counts);
  return summarise_round_trips(round_trips, counts);
}

}  // namespace hapticd::server
