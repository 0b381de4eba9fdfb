#pragma once
// What a finished session reports: loop timing and per-device outcome, as text for the log and as JSON for
// --stats-json.
#include <memory>
#include <string>
#include <vector>

#include "config/session_config.hpp"
#include "executor/executor.hpp"
#include "gate/round_trip_probe.hpp"
#include "group/group_stage.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

class SessionMonitor;

struct SessionReport {
  const SessionConfig* config = nullptr;
  const ExecutorResult* result = nullptr;
  const std::vector<std::unique_ptr<DeviceSession>>* sessions = nullptr;
  const std::vector<std::unique_ptr<GroupStage>>* stages = nullptr;  // the groups (nullptr: none reported)
  // Every fault and recovery of each device (nullptr: only the final state is reported).
  const SessionMonitor* monitor = nullptr;
  std::uint64_t records_written = 0;
  std::uint64_t records_dropped = 0;
  std::uint64_t records_lost = 0;  // a failed recording: not in the file
  bool recording_failed = false;
  // With the DDS interface: state written -> engine -> command accepted, and the cycles until it was applied.
  bool has_round_trip = false;
  RoundTripStatistics round_trip;
  // With the DDS interface: its defences at work.
  struct Dds {
    bool enabled = false;
    std::uint64_t deadline_misses = 0;    // over every device
    std::uint64_t commands_rejected = 0;  // over every device, and commands for unknown devices
    std::uint64_t claims_ended = 0;       // claims whose claimant's participant was gone
    std::uint64_t log_forwarded = 0;      // Cyclone's log lines that reached the log
    std::uint64_t log_suppressed = 0;     // ... and those the rate limit held back
  } dds;
};

std::string report_json(const SessionReport& report);
// A device had a fault during the session, recovered or not (the exit code says so).
bool any_device_faulted(const SessionReport& report);
std::vector<std::string> report_lines(const SessionReport& report);

}  // namespace hapticd::server
