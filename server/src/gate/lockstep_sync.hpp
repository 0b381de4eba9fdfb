#pragma once
// Lockstep through any door, on the loop thread (docs/dds-interface.md, "Lockstep"): after each published cycle the
// loop waits (wall time, bounded) until every engine that answers every state has answered this one, so end-to-end runs
// through a real door are repeatable. The first cycle may wait for an engine to appear at all.
#include <atomic>
#include <cstdint>

#include "config/session_config.hpp"
#include "gate/device_gate.hpp"

namespace hapticd::server {

class LockstepSync {
 public:
  // nudge: wakes the publisher (it repeats the last state for late readers while the first cycle waits).
  LockstepSync(const GateSettings& settings, DeviceGates& devices, std::uint64_t snapshot_interval,
               void (*nudge)(void*), void* nudge_arg)
      : settings_(settings),
        devices_(devices),
        snapshot_interval_(snapshot_interval),
        nudge_(nudge),
        nudge_arg_(nudge_arg) {}

  // Loop thread, after cycle `index` was published; stopping: give up waiting at once.
  void after_cycle(std::uint64_t index, const std::atomic<bool>& stopping) noexcept;
  [[nodiscard]] std::uint64_t timeouts() const noexcept { return timeouts_.load(); }

 private:
  const GateSettings& settings_;
  DeviceGates& devices_;
  std::uint64_t snapshot_interval_;
  void (*nudge_)(void*);
  void* nudge_arg_;
  std::atomic<std::uint64_t> timeouts_{0};
};

}  // namespace hapticd::server
