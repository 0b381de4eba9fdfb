#pragma once
// A DeviceClock for plugin authors: the thread the vendor's SDK calls back on (or that receives the service's
// states) calls tick(); the loop's thread waits in wait_for_tick(). Lock-free: a sequence number and a futex, one
// ticking thread, one waiting thread; the ticking side never blocks.
#include <atomic>
#include <cstdint>

#include "hapticd/device_clock.hpp"
#include "hapticd/export.hpp"

namespace hapticd::realtime {

class HAPTICD_API TickSignal final : public DeviceClock {
 public:
  // The ticking thread: a tick at `time_ns` (CLOCK_MONOTONIC; the current time when omitted). Real-time safe.
  void tick(std::int64_t time_ns) noexcept;
  void tick() noexcept;
  DeviceTick wait_for_tick(std::int64_t until_ns) noexcept override;
  // Any thread: the ticks so far.
  [[nodiscard]] std::uint32_t ticks() const noexcept { return sequence_.load(std::memory_order_acquire); }

  // CLOCK_MONOTONIC now, in ns.
  [[nodiscard]] static std::int64_t now_ns() noexcept;
  // The calling thread waits while `word` holds `expected`, until woken or until `until_ns` (CLOCK_MONOTONIC).
  // False: the time ran out. For hand-offs of their own (a callback that waits for the loop's command).
  static bool wait_while(const std::atomic<std::uint32_t>& word, std::uint32_t expected,
                         std::int64_t until_ns) noexcept;
  static void wake(std::atomic<std::uint32_t>& word) noexcept;

 private:
  std::atomic<std::uint32_t> sequence_{0};
  std::atomic<std::int64_t> time_ns_{-1};
  std::uint32_t seen_ = 0;  // the waiting thread's
};

}  // namespace hapticd::realtime
