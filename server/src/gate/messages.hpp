#pragma once
// The bridge's messages as pure functions of what the loop published (DeviceSnapshot) and the session's
// description: no DDS entity, no thread, no clock - unit-tested without DDS (tests/unit/bridge_messages_test).
// The events a device's state reveals are a pure function of the previous and the current published view.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/spatial.hpp"
#include "hapticd_msg.h"
#include "safety/fault_history.hpp"
#include "session/device_snapshot.hpp"

namespace hapticd::server {

class DeviceRequests;

[[nodiscard]] hapticd_msg_DeviceMode mode_of(const DeviceSnapshot& s) noexcept;
[[nodiscard]] std::uint32_t flags_of(const DeviceSnapshot& s) noexcept;

// What a state message says besides the snapshot.
struct StateLabels {
  std::string_view device;
  std::uint64_t serial = 0;  // the state's serial (cycle / state interval + 1)
  std::string_view scheme;   // the running scheme's name
  std::string_view owner;    // the claim's client id ("": free)
  hapticd_msg_LoopSummary loop{};
};
[[nodiscard]] hapticd_msg_DeviceState state_message(const DeviceSnapshot& s, const StateLabels& labels) noexcept;

// The description of a session's device; start_pose once the loop has run (else all zeros: not known yet).
[[nodiscard]] hapticd_msg_DeviceDescription description_message(const DeviceRequests& device, double rate_hz,
                                                                const std::optional<Pose>& start_pose);

// A fault report into `m` (about 100 kB: the caller owns it, off the stack).
void fill_fault_report(hapticd_msg_FaultReport& m, std::string_view device, int dof,
                       const FaultReport& report) noexcept;

// What the events of a device are derived from: the published mode, fault, count of faults, scheme and
// engine staleness.
struct PublishedView {
  hapticd_msg_DeviceMode mode = hapticd_msg_MODE_STARTING;
  DeviceFault fault = DeviceFault::none;
  std::uint64_t faults = 0;
  int scheme = 0;
  bool stale = false;
  const char* fault_reason = nullptr;  // the device's reason (static text), nullptr if none
};
[[nodiscard]] PublishedView view_of(const DeviceSnapshot& s) noexcept;

struct EventText {
  hapticd_msg_EventKind kind = hapticd_msg_EVENT_MODE;
  std::string code;
  std::string message;
  friend bool operator==(const EventText&, const EventText&) = default;
};
// The events between two published views, in order: a mode change, a fault (also a new fault while the device is
// already safe: the count went up) or a recovery, a scheme switch, the engine turning stale (not back).
[[nodiscard]] std::vector<EventText> events_between(const PublishedView& before, const PublishedView& now,
                                                    const std::vector<std::string>& scheme_names);

}  // namespace hapticd::server
