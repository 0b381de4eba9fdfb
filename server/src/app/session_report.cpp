#include "app/session_report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace hapticd::server {

std::string report_json(const SessionReport& r) {
  const CycleStatistics& s = r.result->statistics;
  const bool lockstep = r.config->server.clock == ClockMode::lockstep;
  std::string out = "{\n";
  out += fmt::format("  \"clock\": \"{}\",\n  \"rate_hz\": {},\n", lockstep ? "lockstep" : "realtime", r.config->server.rate_hz);
  out += fmt::format("  \"cycles\": {},\n  \"overruns\": {},\n  \"max_consecutive_overruns\": {},\n  \"skipped_cycles\": {},\n",
                     s.cycles, s.overruns, s.max_consecutive_overruns, s.skipped_cycles);
  out += fmt::format("  \"loop_time_s\": {:.6f},\n  \"wall_time_s\": {:.6f},\n  \"stop_requested\": {},\n",
                     r.result->loop_time_s, r.result->wall_time_s, r.result->stop_requested);
  out += "  \"wakeup_latency_us\": " + histogram_json(s.wakeup_latency) + ",\n";
  out += "  \"compute_time_us\": " + histogram_json(s.compute_time) + ",\n";
  out += fmt::format("  \"recorder\": {{\"records\": {}, \"dropped\": {}}},\n", r.records_written, r.records_dropped);
  if (r.has_round_trip) {
    const RoundTripStatistics& rt = r.round_trip;
    out += fmt::format("  \"dds_round_trip_us\": {{\"count\": {}, \"p50\": {:.3f}, \"p99\": {:.3f}, \"max\": {:.3f}}},\n",
                       rt.count, rt.p50_us, rt.p99_us, rt.max_us);
    out += fmt::format("  \"dds_applied_after_cycles\": [{}],\n", fmt::join(rt.applied_after_cycles, ", "));
  }
  out += "  \"devices\": [";
  for (std::size_t i = 0; i < r.sessions->size(); ++i) {
    const DeviceSession& d = *(*r.sessions)[i];
    out += fmt::format("{}\n    {{\"name\": \"{}\", \"fault\": \"{}\", \"fault_cycle\": {}, \"saturated_cycles\": {}}}",
                       i ? "," : "", d.name(), to_string(d.fault()), d.fault_cycle(), d.saturated_cycles());
  }
  out += "\n  ]\n}\n";
  return out;
}

std::vector<std::string> report_lines(const SessionReport& r) {
  const CycleStatistics& s = r.result->statistics;
  std::vector<std::string> lines;
  lines.push_back(fmt::format("{} cycles in {:.3f} s loop time ({:.3f} s wall), {} overruns, {} skipped",
                              s.cycles, r.result->loop_time_s, r.result->wall_time_s, s.overruns, s.skipped_cycles));
  if (r.config->server.clock == ClockMode::realtime)
    lines.push_back("wake-up latency: " + histogram_summary(s.wakeup_latency));
  lines.push_back("compute time:    " + histogram_summary(s.compute_time));
  for (const auto& d : *r.sessions)
    lines.push_back(fmt::format("device '{}': {}{}", d->name(),
                                d->fault() == DeviceFault::none ? std::string("ok")
                                                                : fmt::format("FAULT at cycle {}: {}", d->fault_cycle(), to_string(d->fault())),
                                d->saturated_cycles() ? fmt::format(", torque saturated in {} cycles", d->saturated_cycles()) : ""));
  return lines;
}

}  // namespace hapticd::server
