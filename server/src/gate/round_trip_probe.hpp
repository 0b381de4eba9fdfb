#pragma once
// The engine round trip of one device, measured by the DDS bridge (docs/dds-interface.md, "Measured"):
//   round trip: a state written (just before dds_write) -> the command that answers it accepted (validated and
//               handed to the loop), in steady-clock ns;
//   applied:    how many loop cycles after the state's cycle the loop applied that command (1: the very next
//               cycle, the least a sampled loop can do). Seen from the first published state that shows the
//               command applied, so a publisher that skipped snapshots can only make it look later.
// Threads: the publisher calls state_written and command_applied, Cyclone's receive thread command_accepted
// and command_handed_over; the slot hand-off between them is lock-free, the round trips go into a fixed-size
// histogram (no allocation, any session length) under a mutex off the loop.
#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>

#include "executor/latency_histogram.hpp"

namespace hapticd::server {

struct RoundTripStatistics {
  static constexpr std::size_t kAppliedBins = 8;  // applied after 0..6 cycles, 7: 7 or more
  std::uint64_t count = 0;
  double p50_us = 0.0, p99_us = 0.0, max_us = 0.0;
  std::array<std::uint64_t, kAppliedBins> applied_after_cycles{};
  [[nodiscard]] std::uint64_t applied() const noexcept;
};

// The round trips' percentiles (histogram resolution 1.6 %, never understated; the maximum exact) into counts.
[[nodiscard]] RoundTripStatistics summarise_round_trips(const LatencyHistogram& round_trips,
                                                        RoundTripStatistics counts);

class RoundTripProbe {
 public:
  void state_written(std::uint64_t state_serial, std::uint64_t cycle, std::int64_t now_ns) noexcept;
  // An accepted command, before it is handed to the loop (so that command_applied finds it). Returns the write
  // time of the state it answers, 0 when that is unknown (state_serial 0, or a slot since reused).
  std::int64_t command_accepted(std::uint64_t command_serial, std::uint64_t state_serial) noexcept;
  // The same command handed to the loop at now_ns: the end of its round trip (state_written_ns 0: none).
  void command_handed_over(std::int64_t state_written_ns, std::int64_t now_ns) noexcept;
  // A published state of `cycle` shows command_serial as the newest command the loop applied.
  void command_applied(std::uint64_t command_serial, std::uint64_t cycle) noexcept;

  [[nodiscard]] RoundTripStatistics statistics() const;
  // Adds this probe's round trips and counts (a server's devices in one figure: summarise_round_trips).
  void merge_into(LatencyHistogram& round_trips, RoundTripStatistics& counts) const;

 private:
  static constexpr std::size_t kSlots = 4096;
  struct StateSlot {
    std::atomic<std::uint64_t> serial{0};
    std::atomic<std::uint64_t> cycle{0};
    std::atomic<std::int64_t> written_ns{0};
  };
  struct CommandSlot {
    std::atomic<std::uint64_t> serial{0};
    std::atomic<std::uint64_t> state_cycle{0};
  };
  std::array<StateSlot, kSlots> states_{};
  std::array<CommandSlot, kSlots> commands_{};
  std::uint64_t last_applied_ = 0;  // publisher only
  std::array<std::atomic<std::uint64_t>, RoundTripStatistics::kAppliedBins> applied_{};
  mutable std::mutex mutex_;
  LatencyHistogram round_trips_;
};

}  // namespace hapticd::server
