#pragma once
// What a device's loop tells the other threads (docs/architecture.md, "Threads and hand-offs"): its fault and
// counters (atomics), the snapshots for the DDS publisher and the live view, and the newest fault report (lock-free
// latest-value hand-offs), and the log of its faults and recoveries (a lock-free ring the monitor drains). The loop
// writes; nothing here ever blocks it.
#include <atomic>
#include <cstdint>

#include "hapticd/realtime/latest_value.hpp"
#include "hapticd/realtime/spsc_ring.hpp"
#include "safety/device_fault.hpp"
#include "safety/fault_history.hpp"
#include "session/device_snapshot.hpp"

namespace hapticd::server {

// A fault or a recovery of a device, as the session's log keeps it (the final report lists every one).
struct SafetyEvent {
  enum class Kind : std::uint8_t { fault, recovery };
  Kind kind = Kind::fault;
  DeviceFault fault = DeviceFault::none;  // the fault raised, or the one recovered from
  std::uint64_t cycle = 0;
  std::int64_t time_ns = 0;
};

struct DeviceStatus {
  std::atomic<DeviceFault> fault{DeviceFault::none};
  // The device's reason for the fault (Outcome::reason: static text of the plugin, which outlives the session's
  // threads), nullptr if none.
  std::atomic<const char*> fault_reason{nullptr};
  std::atomic<std::uint64_t> fault_cycle{0};
  std::atomic<std::uint64_t> faults{0};  // raised so far (a stop while already safe counts too)
  std::atomic<std::uint64_t> recoveries{0};
  std::atomic<std::uint64_t> refused_recoveries{0};  // the device could not reset its fault
  std::atomic<std::uint64_t> saturated_cycles{0};
  std::atomic<std::uint64_t> limited_cycles{0};
  std::atomic<std::uint64_t> render_limited_cycles{0};
  std::atomic<double> dissipated_j{0.0};
  std::atomic<double> thermal_load{0.0};
  std::atomic<bool> at_rest{true};                       // the safe mode has reached zero torque (or there is no fault)
  std::atomic<bool> passivity_control{false};            // the safety stage's passivity controller is on
  realtime::LatestValue<DeviceSnapshot> snapshots;       // the DDS publisher's
  realtime::LatestValue<DeviceSnapshot> view_snapshots;  // the live view's
  realtime::LatestValue<FaultReport> reports;
  realtime::SpscRing<SafetyEvent> safety_events{256};
  std::atomic<std::uint64_t> lost_safety_events{0};
};

}  // namespace hapticd::server
