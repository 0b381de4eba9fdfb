#pragma once
// What one loop thread runs, as the executor sees it: the executor knows nothing of devices, groups or
// recordings (docs/architecture.md, "Layers"). The cycle of a loop's devices and groups (cycle/LoopCycle) is one.
#include <cstdint>
#include <string>
#include <vector>

#include "hapticd/cycle_time.hpp"

namespace hapticd::server {

class LoopWork {
 public:
  virtual ~LoopWork() = default;
  // The calling thread, before the loop's first cycle (its thread exists, it waits): power what it drives. What
  // cannot be powered is held in its safe state by the work itself.
  virtual void activate() = 0;
  // One cycle; torque_scale ramps the output down at a planned end; consecutive_overruns and lateness_ns feed
  // the watchdogs. Real-time safe.
  virtual void run_cycle(const CycleTime& cycle, double torque_scale, std::uint32_t consecutive_overruns,
                         std::int64_t lateness_ns) noexcept = 0;
  // The loop's thread, when a stop is requested: everything it drives goes to its safe mode. Real-time safe.
  virtual void request_safe_stop() noexcept = 0;
  // Everything it drives is at rest (zero torque after a stop, or never stopped). Real-time safe.
  [[nodiscard]] virtual bool at_rest() const noexcept = 0;
  // The calling thread, after every loop has ended: disable what it drives; what went wrong is added to
  // `warnings` (a device not disabled cleanly) and `plugin_errors` (what plugins threw as they were deactivated).
  virtual void deactivate(std::vector<std::string>& warnings, std::vector<std::string>& plugin_errors) = 0;
  // The names of what it drives, for the loop's result.
  [[nodiscard]] virtual std::vector<std::string> device_names() const = 0;
};

}  // namespace hapticd::server
