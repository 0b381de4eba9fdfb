#include "app/session_monitor.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "doors/doors.hpp"
#include "recorder/recorder.hpp"
#include "safety/fault_history.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {
namespace {

// The fault and a summary of the cycles before it (the full history goes to the fault report topic).
void log_fault_report(const DeviceSession& d, const FaultReport& r) {
  double speed = 0.0, joint_speed = 0.0, torque = 0.0, force = 0.0;
  for (std::uint32_t k = 0; k < r.count; ++k) {
    const HistoryRecord& c = r.records[k];
    speed = std::max(speed, c.handle_velocity.norm());
    if (c.velocity.size() > 0) joint_speed = std::max(joint_speed, c.velocity.cwiseAbs().maxCoeff());
    if (c.torque.size() > 0) torque = std::max(torque, c.torque.cwiseAbs().maxCoeff());
    force = std::max(force, c.operator_force.norm());
  }
  std::string governed(governed_by(r.fault));
  for (std::size_t at = governed.find("<device>"); at != std::string::npos; at = governed.find("<device>", at))
    governed.replace(at, 8, d.name());
  spdlog::error(
      "device '{}' fault {} at cycle {}: {}; safe mode (damping, then zero torque). Last {} cycles: "
      "largest handle speed {:.3f} m/s, joint speed {:.3f}, torque {:.2f}, operator force {:.1f} N{}",
      d.name(), fault_code(r.fault), r.cycle,
      std::string(to_string(r.fault)) + (r.reason[0] != '\0' ? ": " + std::string(r.reason.data()) : std::string()),
      r.count, speed, joint_speed, torque, force, governed.empty() ? "" : ". Governed by " + governed);
}

}  // namespace

SessionMonitor::SessionMonitor(std::vector<DeviceSession*> devices, Doors* doors,
                               const std::atomic<bool>* stop_requested, const Recorder* recorder)
    : devices_(std::move(devices)),
      doors_(doors),
      stop_requested_(stop_requested),
      reported_(devices_.size(), DeviceFault::none),
      logs_(devices_.size()),
      report_(std::make_unique<FaultReport>()),
      recorder_(recorder) {}

SessionMonitor::~SessionMonitor() = default;

void SessionMonitor::poll() {
  for (auto* d : devices_) {
    d->service();
    for (const std::string& e : d->take_plugin_errors()) {
      spdlog::error("device '{}': {}", d->name(), e);
      ++plugin_errors_;
    }
  }
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    DeviceSession& d = *devices_[i];
    if (d.status().take_fault_report(*report_)) {
      ++reports_;
      log_fault_report(d, *report_);
      if (doors_ != nullptr) doors_->publish_fault_report(i, *report_);
    }
    SafetyEvent e;
    while (d.status().take_safety_event(e)) {
      if (e.kind == SafetyEvent::Kind::recovery)
        spdlog::info("device '{}' recovered from {} on request at cycle {}", d.name(), fault_code(e.fault), e.cycle);
      Log& log = logs_[i];
      if (log.events.size() < kMaxLoggedEvents) {
        log.events.push_back(e);
      } else {
        ++log.not_kept;
      }
    }
    const DeviceFault f = d.status().fault();
    if (f == reported_[i]) continue;
    if (f == DeviceFault::configure || f == DeviceFault::device_enable || f == DeviceFault::device_homing) {
      spdlog::error("device '{}' is in its safe state: {}", d.name(), d.status().fault_text());
    }
    reported_[i] = f;
  }
  if (recorder_ != nullptr && recorder_->failed() && !recording_failure_logged_) {
    recording_failure_logged_ = true;
    const std::string message = recorder_->error() + "; the recording stops here (" +
                                std::to_string(recorder_->lost()) + " device-cycles lost so far), the session runs on";
    spdlog::error("{}", message);
    if (doors_ != nullptr) doors_->announce(hapticd_msg_EVENT_RECORDING, "recording_failed", message);
  }
  if (stop_requested_ != nullptr && stop_requested_->load() && !stop_logged_) {
    spdlog::info("stop requested: every device stops through its safe mode (damping, then zero torque)");
    stop_logged_ = true;
  }
}

}  // namespace hapticd::server
