#include "dds/round_trip_probe.hpp"

#include <algorithm>
#include <numeric>

namespace hapticd::server {

std::uint64_t RoundTripStatistics::applied() const noexcept {
  return std::accumulate(applied_after_cycles.begin(), applied_after_cycles.end(), std::uint64_t{0});
}

RoundTripProbe::RoundTripProbe() { round_trips_ns_.reserve(1 << 16); }

void RoundTripProbe::state_written(std::uint64_t state_serial, std::uint64_t cycle, std::int64_t now_ns) noexcept {
  StateSlot& s = states_[state_serial % kSlots];
  s.serial.store(0, std::memory_order_relaxed);  // invalid while it changes (a sequence lock)
  std::atomic_thread_fence(std::memory_order_release);
  s.cycle.store(cycle, std::memory_order_relaxed);
  s.written_ns.store(now_ns, std::memory_order_relaxed);
  s.serial.store(state_serial, std::memory_order_release);
}

bool RoundTripProbe::read_state(std::uint64_t state_serial, std::uint64_t& cycle, std::int64_t& written_ns) const noexcept {
  if (state_serial == 0) return false;
  const StateSlot& s = states_[state_serial % kSlots];
  if (s.serial.load(std::memory_order_acquire) != state_serial) return false;  // too old: its slot was reused
  cycle = s.cycle.load(std::memory_order_relaxed);
  written_ns = s.written_ns.load(std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_acquire);
  return s.serial.load(std::memory_order_relaxed) == state_serial;  // not reused while we read it
}

void RoundTripProbe::command_accepted(std::uint64_t command_serial, std::uint64_t state_serial) noexcept {
  std::uint64_t cycle = 0;
  std::int64_t written = 0;
  if (!read_state(state_serial, cycle, written)) return;
  CommandSlot& c = commands_[command_serial % kSlots];
  c.serial.store(0, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  c.state_cycle.store(cycle, std::memory_order_relaxed);
  c.serial.store(command_serial, std::memory_order_release);
}

void RoundTripProbe::command_handed_over(std::uint64_t state_serial, std::int64_t now_ns) {
  std::uint64_t cycle = 0;
  std::int64_t written = 0;
  if (!read_state(state_serial, cycle, written)) return;
  std::lock_guard lock(mutex_);
  if (round_trips_ns_.size() < kMaxSamples) round_trips_ns_.push_back(now_ns - written);
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

void RoundTripProbe::merge_into(std::vector<std::int64_t>& round_trips_ns, RoundTripStatistics& counts) const {
  {
    std::lock_guard lock(mutex_);
    round_trips_ns.insert(round_trips_ns.end(), round_trips_ns_.begin(), round_trips_ns_.end());
  }
  for (std::size_t i = 0; i < applied_.size(); ++i) counts.applied_after_cycles[i] += applied_[i].load(std::memory_order_relaxed);
}

RoundTripStatistics summarise_round_trips(std::vector<std::int64_t> samples, RoundTripStatistics counts) {
  counts.count = samples.size();
  if (samples.empty()) return counts;
  std::sort(samples.begin(), samples.end());
  const auto at = [&](double q) {
    return static_cast<double>(samples[static_cast<std::size_t>(q * static_cast<double>(samples.size() - 1))]) * 1e-3;
  };
  counts.p50_us = at(0.5);
  counts.p99_us = at(0.99);
  counts.max_us = static_cast<double>(samples.back()) * 1e-3;
  return counts;
}

RoundTripStatistics RoundTripProbe::statistics() const {
  std::vector<std::int64_t> samples;
  RoundTripStatistics counts;
  merge_into(samples, counts);
  return summarise_round_trips(std::move(samples), counts);
}

}  // namespace hapticd::server
