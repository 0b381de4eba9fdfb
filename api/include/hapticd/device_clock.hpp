#pragma once
// A device whose SDK or service owns the servo loop: OpenHaptics calls its callback from its own scheduler, Haply's
// Inverse Service answers one state per message. With `server.clock: device` the loop that drives such a device
// runs one cycle per tick of the device instead of sleeping to deadlines of its own (docs/architecture.md, "Device
// clocks"); a device that stops ticking is a loop_stall, as a loop that wakes late is.
#include <cstdint>

namespace hapticd {

// What a wait for the device's next tick found.
struct DeviceTick {
  std::int64_t time_ns = -1;  // CLOCK_MONOTONIC time of the newest tick; -1: none came before the wait ended
  std::uint32_t count = 0;    // ticks since the previous wait (more than one: the loop missed some)
};

class DeviceClock {
 public:
  virtual ~DeviceClock() = default;
  // The loop's thread, between cycles. Returns at once with the ticks that came since the previous call, if any;
  // else waits until the next tick or until `until_ns` (CLOCK_MONOTONIC) has passed. Real-time safe: no allocation,
  // no lock (a futex wait), no exception.
  virtual DeviceTick wait_for_tick(std::int64_t until_ns) noexcept = 0;
};

}  // namespace hapticd
