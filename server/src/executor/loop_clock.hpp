#pragma once
#include <cstdint>

#include "hapticd/device_clock.hpp"

namespace hapticd::server {

// The clock the loop sleeps on. Real time: CLOCK_MONOTONIC with absolute-deadline sleeps. Lockstep: a virtual
// clock that jumps to each deadline at once, so a session runs as fast as the machine allows and its results
// do not depend on the machine's load. Device: the ticks of a device whose SDK owns the servo loop.
class LoopClock {
 public:
  virtual ~LoopClock() = default;
  [[nodiscard]] virtual std::int64_t now_ns() noexcept = 0;
  virtual void sleep_until(std::int64_t deadline_ns) noexcept = 0;
  [[nodiscard]] virtual bool is_virtual() const noexcept = 0;
  // Waits for the cycle due at `deadline_ns` and returns when it is due: the deadline itself, or for a device's
  // clock the time of the device's tick; `missed` is set to the periods that went by unseen (ticks the loop missed).
  virtual std::int64_t wait_for_cycle(std::int64_t deadline_ns, std::uint64_t& missed) noexcept {
    missed = 0;
    sleep_until(deadline_ns);
    return deadline_ns;
  }
  // The schedule is the device's (cycles follow its ticks), not the loop's deadlines.
  [[nodiscard]] virtual bool follows_device() const noexcept { return false; }
};

class MonotonicClock final : public LoopClock {
 public:
  std::int64_t now_ns() noexcept override;
  void sleep_until(std::int64_t deadline_ns) noexcept override;
  bool is_virtual() const noexcept override { return false; }
};

class VirtualClock final : public LoopClock {
 public:
  std::int64_t now_ns() noexcept override { return now_ns_; }
  void sleep_until(std::int64_t deadline_ns) noexcept override {
    if (deadline_ns > now_ns_) now_ns_ = deadline_ns;
  }
  bool is_virtual() const noexcept override { return true; }

 private:
  std::int64_t now_ns_ = 0;
};

// The ticks of a device (`server.clock: device`). A cycle runs at each tick; the cycle's time is the tick's. When no
// tick comes within `stall_ns` of when it was due, the cycle runs anyway that late - the devices' stall watchdog
// sees the lateness (loop_stall) - and the loop runs on the monotonic clock, one cycle per period, so that the
// safe modes fade and damp, until the device ticks again. The first tick may take `first_tick_ns`.
class DeviceTickClock final : public LoopClock {
 public:
  DeviceTickClock(DeviceClock& device, std::int64_t stall_ns, std::int64_t first_tick_ns) noexcept
      : device_(device), stall_ns_(stall_ns), first_tick_ns_(first_tick_ns) {}
  std::int64_t now_ns() noexcept override;
  void sleep_until(std::int64_t deadline_ns) noexcept override;
  bool is_virtual() const noexcept override { return false; }
  std::int64_t wait_for_cycle(std::int64_t deadline_ns, std::uint64_t& missed) noexcept override;
  bool follows_device() const noexcept override { return true; }

 private:
  DeviceClock& device_;
  std::int64_t stall_ns_;
  std::int64_t first_tick_ns_;
  bool started_ = false;
  bool free_running_ = false;  // the device stopped ticking: cycles on the monotonic clock until it ticks again
};

// Monotonic time for measuring compute time, whichever clock the loop runs on.
std::int64_t monotonic_now_ns() noexcept;

}  // namespace hapticd::server
