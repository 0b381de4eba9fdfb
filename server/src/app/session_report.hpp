#pragma once
// What a finished session reports: loop timing and per-device outcome, as text for the log and as JSON for
// --stats-json.
#include <memory>
#include <string>
#include <vector>

#include "config/session_config.hpp"
#include "dds/round_trip_probe.hpp"
#include "executor/executor.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

struct SessionReport {
  const SessionConfig* config = nullptr;
  const ExecutorResult* result = nullptr;
  const std::vector<std::unique_ptr<DeviceSession>>* sessions = nullptr;
  std::uint64_t records_written = 0;
  std::uint64_t records_dropped = 0;
  // With the DDS interface: state written -> engine -> command accepted, and the cycles until it was applied.
  bool has_round_trip = false;
  RoundTripStatistics round_trip;
};

std::string report_json(const SessionReport& report);
std::vector<std::string> report_lines(const SessionReport& report);

}  // namespace hapticd::server
