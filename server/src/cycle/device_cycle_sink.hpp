#pragma once
// Told by a loop, on its thread, after each device has written this cycle's torques: the recorder takes the
// device's cycle here. Defined with the cycle so that the cycle needs nothing of what sits above it.
#include <cstddef>
#include <cstdint>

#include "hapticd/cycle_time.hpp"

namespace hapticd::server {

class DeviceSession;

class DeviceCycleSink {
 public:
  virtual ~DeviceCycleSink() = default;
  // How many loops may hand cycles over at once (one each: `producer` is the loop's number below this).
  [[nodiscard]] virtual std::size_t producers() const noexcept = 0;
  // Device `index` (its number in the session) after limit_and_write(); lateness_ns: the loop woke this late;
  // compute_ns: from the cycle's start to this device's torques written. Real-time safe.
  virtual void device_written(std::size_t producer, const DeviceSession& device, std::uint16_t index,
                              const CycleTime& cycle, std::int64_t lateness_ns, std::int64_t compute_ns) noexcept = 0;
};

}  // namespace hapticd::server
