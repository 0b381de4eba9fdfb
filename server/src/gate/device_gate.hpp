#pragma once
// What the gate keeps about one device (docs/architecture.md, "The gate and its doors"): its faces, who owns it
// (the command gate and the claim, under one lock), the E-stops that hold it, the lockstep hand-shake and the
// counters. DeviceGates is the list, fixed once the gate is built, with the session's device groups.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "config/session_config.hpp"
#include "gate/command_gate.hpp"
#include "gate/round_trip_probe.hpp"
#include "gate/stop_latches.hpp"

namespace hapticd::server {

class DeviceRequests;
class DeviceSession;
class DeviceStatus;
class GroupStage;

// A device group as the gate sees it: its stage (the group snapshots) and its devices' places in DeviceGates.
struct GroupGate {
  std::string name;
  GroupStage* stage;
  std::vector<std::size_t> members;  // indices into DeviceGates, in the group's order
  std::uint64_t serial = 0;          // group states published (publisher thread)
};

struct DeviceGate {
  DeviceGate(std::size_t index, DeviceSession* s, const GateSettings& settings);

  std::size_t index;  // in the session (and the gate's lists)
  // The device's faces for the threads other than its loop (session/device_session.hpp): what the gate may ask
  // of it (and its name, description and schemes), and what its loop tells the gate (the state snapshots and
  // fault reports, whose outlets the state fan-out alone takes).
  DeviceRequests* device;
  DeviceStatus* status;
  // Ownership: the gate (owner, order, freshness; counters) and the claim, changed by command admission and the
  // request dispatcher, read by the others.
  mutable std::mutex mutex;
  CommandGate gate;
  Sender claim_channel;         // the peer and channel that made the claim (the channel gone: the claimant left)
  std::int64_t claimed_ns = 0;  // steady clock; claim_grace_s runs from here
  StopLatches stops;            // the E-stops requested through a door that still hold the device
  // The service thread only: since when the claimant has shown no sign of life (0: it has).
  std::int64_t silent_since_ns = 0;
  std::int64_t silent_claimed_ns = 0;  // the claim it counts for
  // Lockstep: the newest state serial an accepted command answered; whether the owner answers every state.
  std::atomic<std::uint64_t> answered{0};
  std::atomic<bool> synced{false};
  std::atomic<std::uint64_t> requests{0};
  std::atomic<std::uint64_t> states{0};       // published (telemetry)
  std::atomic<std::int64_t> loop_time_ns{0};  // of the newest published state (events from any thread)
  RoundTripProbe round_trip;
  // Rejected commands announced so far per reason (under the gate's admit lock: the first, then every 100th).
  std::array<std::uint64_t, dds::kRejectReasons> reject_events{};
};

class DeviceGates {
 public:
  // stages: the session's device groups (their devices are among the sessions).
  DeviceGates(const std::vector<DeviceSession*>& sessions, const std::vector<GroupStage*>& stages,
              const GateSettings& settings);

  [[nodiscard]] std::size_t size() const noexcept { return devices_.size(); }
  DeviceGate& operator[](std::size_t i) noexcept { return *devices_[i]; }
  const DeviceGate& operator[](std::size_t i) const noexcept { return *devices_[i]; }
  // The device named so, nullptr if the server does not drive it.
  [[nodiscard]] DeviceGate* find(std::string_view device) noexcept;
  [[nodiscard]] const DeviceGate* find(std::string_view device) const noexcept;
  // The device groups, and the one named so (nullptr: none).
  [[nodiscard]] std::vector<GroupGate>& groups() noexcept { return groups_; }
  [[nodiscard]] const std::vector<GroupGate>& groups() const noexcept { return groups_; }
  [[nodiscard]] GroupGate* find_group(std::string_view group) noexcept;
  [[nodiscard]] const GroupGate* find_group(std::string_view group) const noexcept;
  // Whether a request may name `target`: a device, a group, or "*" (every device).
  [[nodiscard]] bool request_target(std::string_view target) const noexcept;
  auto begin() noexcept { return devices_.begin(); }
  auto end() noexcept { return devices_.end(); }
  auto begin() const noexcept { return devices_.begin(); }
  auto end() const noexcept { return devices_.end(); }

  // A command for a device it does not name, or for a device this server does not have (malformed; any door).
  void count_unknown_command() noexcept { unknown_commands_.fetch_add(1, std::memory_order_relaxed); }
  // A request naming a device or group this server does not have (left unanswered: another server may have it).
  void count_unknown_request() noexcept { unknown_requests_.fetch_add(1, std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t unknown_device_commands() const noexcept { return unknown_commands_.load(); }
  [[nodiscard]] std::uint64_t unknown_device_requests() const noexcept { return unknown_requests_.load(); }

 private:
  std::vector<std::unique_ptr<DeviceGate>> devices_;
  std::vector<GroupGate> groups_;
  std::atomic<std::uint64_t> unknown_commands_{0};
  std::atomic<std::uint64_t> unknown_requests_{0};
};

}  // namespace hapticd::server
