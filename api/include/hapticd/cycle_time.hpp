#pragma once
#include <cstdint>

namespace hapticd {

// Time of one control cycle. time_ns is the cycle's nominal (scheduled) time since the session started, on
// the loop clock: the monotonic clock in real-time mode, the virtual clock in lockstep mode. Using the nominal
// time keeps simulated devices deterministic in both modes. index = time_ns / period_ns, the period number;
// after an overrun the loop skips the periods it missed, so consecutive cycles may differ by more than one.
struct CycleTime {
  std::int64_t time_ns = 0;
  std::int64_t period_ns = 0;
  std::uint64_t index = 0;

  [[nodiscard]] double time_s() const noexcept { return static_cast<double>(time_ns) * 1e-9; }
  [[nodiscard]] double period_s() const noexcept { return static_cast<double>(period_ns) * 1e-9; }
};

}  // namespace hapticd
