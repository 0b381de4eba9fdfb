#pragma once
// What the bridge's parts share about one device (docs/architecture.md, "The DDS bridge"): its faces, who
// owns it (the command gate and the claim, under one lock), the lockstep hand-shake and the counters. Each part
// keeps the rest of its per-device state itself. DeviceLinks is the list, fixed once the bridge is built: it also
// holds the readers' topic filters (only samples for these devices are stored) and what they dropped.
#include <dds/dds.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "bridge/command_gate.hpp"
#include "bridge/round_trip_probe.hpp"
#include "bridge/stop_latches.hpp"
#include "config/session_config.hpp"

namespace hapticd::server {

class DeviceRequests;
class DeviceSession;
class DeviceStatus;
class GroupStage;

// A device group as the bridge sees it: its stage (the group snapshots) and its devices' places in DeviceLinks.
struct GroupLink {
  std::string name;
  GroupStage* stage;
  std::vector<std::size_t> members;  // indices into DeviceLinks, in the group's order
  std::uint64_t serial = 0;          // group states published (publisher thread)
};

struct DeviceLink {
  DeviceLink(std::size_t index, DeviceSession* s, const DdsSettings& settings);

  std::size_t index;  // in the session (and the bridge's lists)
  // The device's faces for the threads other than its loop (session/device_session.hpp): what the bridge may ask
  // of it (and its name, description and schemes), and what its loop tells the bridge (the state snapshots and
  // fault reports, whose outlets the state publisher alone takes).
  DeviceRequests* device;
  DeviceStatus* status;
  // Ownership: the gate (owner, order, freshness; counters) and the claim, changed by the command listener and
  // the request dispatcher, read by the others.
  mutable std::mutex mutex;
  CommandGate gate;
  dds_instance_handle_t claim_writer = 0;  // the request writer that made the claim (gone: the claimant left)
  std::int64_t claimed_ns = 0;             // steady clock; claim_grace_s runs from here
  StopLatches stops;                       // the E-stops requested over DDS that still hold the device
  // The request dispatcher's thread only: since when the claimant has had no live command writer (0: it has).
  std::int64_t silent_since_ns = 0;
  std::int64_t silent_claimed_ns = 0;  // the claim it counts for
  // Lockstep: the newest state serial an accepted command answered; whether the owner answers every state.
  std::atomic<std::uint64_t> answered{0};
  std::atomic<bool> synced{false};
  // The device's instance on the command reader (listener -> receiver: deadline misses are per instance).
  std::atomic<dds_instance_handle_t> instance{0};
  std::atomic<std::uint64_t> deadline_misses{0};
  std::atomic<std::uint64_t> requests{0};
  std::atomic<std::uint64_t> states{0};       // published (telemetry)
  std::atomic<std::int64_t> loop_time_ns{0};  // of the newest published state (events from any thread)
  RoundTripProbe round_trip;
  // Rejected commands announced so far per reason (the command listener only: the first, then every 100th).
  std::array<std::uint64_t, dds::kRejectReasons> reject_events{};
};

class DeviceLinks {
 public:
  // stages: the session's device groups (their devices are among the sessions).
  DeviceLinks(const std::vector<DeviceSession*>& sessions, const std::vector<GroupStage*>& stages,
              const DdsSettings& settings);

  [[nodiscard]] std::size_t size() const noexcept { return links_.size(); }
  DeviceLink& operator[](std::size_t i) noexcept { return *links_[i]; }
  const DeviceLink& operator[](std::size_t i) const noexcept { return *links_[i]; }
  // The device named so, nullptr if the server does not drive it.
  [[nodiscard]] DeviceLink* find(std::string_view device) noexcept;
  // The device groups, and the one named so (nullptr: none).
  [[nodiscard]] std::vector<GroupLink>& groups() noexcept { return groups_; }
  [[nodiscard]] const std::vector<GroupLink>& groups() const noexcept { return groups_; }
  [[nodiscard]] GroupLink* find_group(std::string_view group) noexcept;
  auto begin() noexcept { return links_.begin(); }
  auto end() noexcept { return links_.end(); }
  auto begin() const noexcept { return links_.begin(); }
  auto end() const noexcept { return links_.end(); }

  // The readers' topic filters (Cyclone's receive threads): samples for another device are dropped before the
  // reader stores them - an attacker inventing device names creates no state - and counted.
  [[nodiscard]] dds_topic_filter command_filter() noexcept;
  [[nodiscard]] dds_topic_filter request_filter() noexcept;
  [[nodiscard]] dds_topic_filter group_command_filter() noexcept;
  // A command for a device it does not name, or for a device this server does not have (counted as malformed).
  void count_unknown_command() noexcept { unknown_commands_.fetch_add(1, std::memory_order_relaxed); }
  // Engine commands naming a device this server does not have (malformed; never applied).
  [[nodiscard]] std::uint64_t unknown_device_commands() const noexcept { return unknown_commands_.load(); }
  // Requests naming a device or group this server does not have (left unanswered: another server may have it).
  [[nodiscard]] std::uint64_t unknown_device_requests() const noexcept { return unknown_requests_.load(); }

 private:
  static bool command_for_us(const void* sample, void* self);
  static bool request_for_us(const void* sample, void* self);
  static bool group_command_for_us(const void* sample, void* self);

  std::vector<std::unique_ptr<DeviceLink>> links_;
  std::vector<GroupLink> groups_;
  std::atomic<std::uint64_t> unknown_commands_{0};
  std::atomic<std::uint64_t> unknown_requests_{0};
};

}  // namespace hapticd::server
