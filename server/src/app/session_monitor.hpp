#pragma once
// The executor's monitor, on its non-real-time thread: services the devices (scheme switches finish off the
// loop), takes each device's fault report from its lock-free outbox, logs it and publishes it on the DDS
// interface, and logs faults, recoveries and a stop request once each.
#include <atomic>
#include <memory>
#include <vector>

#include "safety/device_fault.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

class DeviceSession;
class Doors;
class Recorder;
struct FaultReport;

class SessionMonitor {
 public:
  // doors may be nullptr (no DDS interface, no engine socket); stop_requested may be nullptr (nothing to log).
  // recorder may be nullptr; a failing recording is logged and announced once.
  SessionMonitor(std::vector<DeviceSession*> devices, Doors* doors, const std::atomic<bool>* stop_requested = nullptr,
                 const Recorder* recorder = nullptr);
  ~SessionMonitor();
  SessionMonitor(const SessionMonitor&) = delete;
  SessionMonitor& operator=(const SessionMonitor&) = delete;

  // One pass; the executor calls it every few milliseconds.
  void poll();
  // Fault reports taken (and published) so far.
  [[nodiscard]] std::size_t reports() const noexcept { return reports_; }
  // Plugins that threw as the monitor deactivated their scheme (logged as errors) so far.
  [[nodiscard]] std::size_t plugin_errors() const noexcept { return plugin_errors_; }
  // Every fault and recovery of device i so far, oldest first (at most kMaxLoggedEvents; the rest counted).
  [[nodiscard]] const std::vector<SafetyEvent>& safety_log(std::size_t i) const { return logs_.at(i).events; }
  [[nodiscard]] std::uint64_t safety_events_not_kept(std::size_t i) const { return logs_.at(i).not_kept; }
  static constexpr std::size_t kMaxLoggedEvents = 10000;

 private:
  std::vector<DeviceSession*> devices_;
  Doors* doors_;
  const std::atomic<bool>* stop_requested_;
  std::vector<DeviceFault> reported_;
  struct Log {
    std::vector<SafetyEvent> events;
    std::uint64_t not_kept = 0;
  };
  std::vector<Log> logs_;
  std::unique_ptr<FaultReport> report_;  // large: not on the stack
  std::size_t reports_ = 0;
  std::size_t plugin_errors_ = 0;
  bool stop_logged_ = false;
  const Recorder* recorder_;
  bool recording_failure_logged_ = false;
};

}  // namespace hapticd::server
