#pragma once
// Always-on per-cycle timing of the loop: wake-up latency (how late the loop woke after its deadline: the
// period error), compute time (wake-up to the end of the cycle's work), overruns (a cycle that ended after
// the next deadline) and skipped cycles. Recording is real-time safe; reading is done after the loop ends.
#include <cstdint>
#include <string>

#include "executor/latency_histogram.hpp"

namespace hapticd::server {

struct CycleStatistics {
  LatencyHistogram wakeup_latency;  // real-time clock only (zero by construction in lockstep)
  LatencyHistogram compute_time;
  std::uint64_t cycles = 0;
  std::uint64_t overruns = 0;
  std::uint64_t max_consecutive_overruns = 0;
  std::uint64_t skipped_cycles = 0;
  std::uint64_t consecutive_overruns = 0;

  void record(std::int64_t wakeup_latency_ns, std::int64_t compute_ns, bool overrun) noexcept {
    wakeup_latency.record(wakeup_latency_ns);
    compute_time.record(compute_ns);
    ++cycles;
    if (overrun) {
      ++overruns;
      ++consecutive_overruns;
      if (consecutive_overruns > max_consecutive_overruns) max_consecutive_overruns = consecutive_overruns;
    } else {
      consecutive_overruns = 0;
    }
  }
};

// {"min":..,"mean":..,"p50":..,"p90":..,"p99":..,"p999":..,"max":..,"histogram":[[lower_us,count],..]} in us.
std::string histogram_json(const LatencyHistogram& h);
// "p50 1.2 us, p99 3.4 us, max 10.1 us"
std::string histogram_summary(const LatencyHistogram& h);

}  // namespace hapticd::server
