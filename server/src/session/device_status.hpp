#pragma once
// What a device's loop tells the other threads (docs/architecture.md, "Threads and hand-offs"): the read side of a
// device. Its fault and counters (atomics), the snapshots for the DDS publisher and the live view and the newest
// fault report (lock-free latest-value hand-offs), and the log of its faults and recoveries (a lock-free ring the
// monitor drains). Any thread reads; only the device's loop writes (DeviceSession, a friend); nothing here ever
// blocks the loop. Each take_* outlet has one reader at a time.
#include <atomic>
#include <cstdint>
#include <string>

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

class DeviceStatus {
 public:
  // The fault the device is in (none: it runs its chain).
  [[nodiscard]] DeviceFault fault() const noexcept { return fault_.load(std::memory_order_acquire); }
  // The device's reason for the fault (or for a refused fault reset), nullptr if it gave none.
  [[nodiscard]] const char* fault_reason() const noexcept { return fault_reason_.load(std::memory_order_relaxed); }
  // The fault as a sentence with the device's reason ("device read failed: joint 2 ..."); "" if none.
  [[nodiscard]] std::string fault_text() const;
  [[nodiscard]] std::uint64_t fault_cycle() const noexcept { return fault_cycle_.load(std::memory_order_relaxed); }
  // Faults raised so far (a stop while already safe counts too), recoveries made and refused by the device.
  [[nodiscard]] std::uint64_t faults_raised() const noexcept { return faults_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t recoveries() const noexcept { return recoveries_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t refused_recoveries() const noexcept {
    return refused_recoveries_.load(std::memory_order_relaxed);
  }
  // The safety supervisor's counters and gauges.
  [[nodiscard]] std::uint64_t saturated_cycles() const noexcept {
    return saturated_cycles_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t limited_cycles() const noexcept {
    return limited_cycles_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t render_limited_cycles() const noexcept {
    return render_limited_cycles_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] double dissipated_j() const noexcept { return dissipated_j_.load(std::memory_order_relaxed); }
  [[nodiscard]] double thermal_load() const noexcept { return thermal_load_.load(std::memory_order_relaxed); }
  // The safe mode has reached zero torque (or there is no fault).
  [[nodiscard]] bool at_rest() const noexcept { return at_rest_.load(std::memory_order_acquire); }
  // The safety stage's passivity controller is on (as of the last cycle).
  [[nodiscard]] bool passivity_control() const noexcept { return passivity_control_.load(std::memory_order_acquire); }

  // The newest snapshot for the DDS publisher (DeviceSession::set_snapshot_interval); false if none since the
  // last take.
  bool take_snapshot(DeviceSnapshot& out) noexcept { return snapshots_.take(out); }
  // The live view's snapshots: a hand-off of their own, at their own interval (the two readers never take each
  // other's).
  bool take_view_snapshot(DeviceSnapshot& out) noexcept { return view_snapshots_.take(out); }
  // The newest fault report (the fault and the cycles before it); false if none since the last take.
  bool take_fault_report(FaultReport& out) noexcept { return reports_.take(out); }
  // The next fault or recovery from the device's log, oldest first; false if none. What did not fit is counted.
  bool take_safety_event(SafetyEvent& out) noexcept { return safety_events_.try_pop(out); }
  [[nodiscard]] std::uint64_t lost_safety_events() const noexcept {
    return lost_safety_events_.load(std::memory_order_relaxed);
  }

 private:
  friend class DeviceSession;  // the loop: the only writer

  std::atomic<DeviceFault> fault_{DeviceFault::none};
  // Outcome::reason: static text of the plugin, which outlives the session's threads.
  std::atomic<const char*> fault_reason_{nullptr};
  std::atomic<std::uint64_t> fault_cycle_{0};
  std::atomic<std::uint64_t> faults_{0};
  std::atomic<std::uint64_t> recoveries_{0};
  std::atomic<std::uint64_t> refused_recoveries_{0};
  std::atomic<std::uint64_t> saturated_cycles_{0};
  std::atomic<std::uint64_t> limited_cycles_{0};
  std::atomic<std::uint64_t> render_limited_cycles_{0};
  std::atomic<double> dissipated_j_{0.0};
  std::atomic<double> thermal_load_{0.0};
  std::atomic<bool> at_rest_{true};
  std::atomic<bool> passivity_control_{false};
  realtime::LatestValue<DeviceSnapshot> snapshots_;       // the DDS publisher's
  realtime::LatestValue<DeviceSnapshot> view_snapshots_;  // the live view's
  realtime::LatestValue<FaultReport> reports_;
  realtime::SpscRing<SafetyEvent> safety_events_{256};
  std::atomic<std::uint64_t> lost_safety_events_{0};
};

}  // namespace hapticd::server
