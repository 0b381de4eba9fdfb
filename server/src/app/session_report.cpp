#include "app/session_report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/session_monitor.hpp"

namespace hapticd::server {
namespace {

const char* kind_name(SafetyEvent::Kind k) { return k == SafetyEvent::Kind::fault ? "fault" : "recovery"; }

// Text in a JSON string: quotes, backslashes and control characters escaped.
std::string json_text(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
    } else {
      out += c;
    }
  }
  return out;
}

std::string events_json(const SessionReport& r, std::size_t device) {
  if (r.monitor == nullptr) return "[]";
  std::string out = "[";
  const auto& log = r.monitor->safety_log(device);
  for (std::size_t k = 0; k < log.size(); ++k)
    out += fmt::format("{}{{\"event\": \"{}\", \"fault\": \"{}\", \"cycle\": {}, \"time_s\": {:.6f}}}", k ? ", " : "",
                       kind_name(log[k].kind), fault_code(log[k].fault), log[k].cycle,
                       static_cast<double>(log[k].time_ns) * 1e-9);
  return out + "]";
}

std::vector<std::string> quoted(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const std::string& n : names) out.push_back("\"" + json_text(n) + "\"");
  return out;
}

}  // namespace

bool any_device_faulted(const SessionReport& r) {
  for (const auto& d : *r.sessions)
    if (d->status().faults_raised() > 0 || d->status().fault() != DeviceFault::none) return true;
  return false;
}

std::string report_json(const SessionReport& r) {
  const CycleStatistics& s = r.result->statistics;
  std::string out = "{\n";
  out += fmt::format("  \"clock\": \"{}\",\n  \"rate_hz\": {},\n", clock_name(r.config->server.clock),
                     r.config->server.rate_hz);
  out += fmt::format(
      "  \"cycles\": {},\n  \"overruns\": {},\n  \"max_consecutive_overruns\": {},\n  \"skipped_cycles\": {},\n",
      s.cycles, s.overruns, s.max_consecutive_overruns, s.skipped_cycles);
  out += fmt::format("  \"loop_time_s\": {:.6f},\n  \"wall_time_s\": {:.6f},\n  \"stop_requested\": {},\n",
                     r.result->loop_time_s, r.result->wall_time_s, r.result->stop_requested);
  out += "  \"wakeup_latency_us\": " + histogram_json(s.wakeup_latency) + ",\n";
  out += "  \"compute_time_us\": " + histogram_json(s.compute_time) + ",\n";
  out += "  \"loops\": [";
  for (std::size_t k = 0; k < r.result->loops.size(); ++k) {
    const LoopResult& l = r.result->loops[k];
    out += fmt::format(
        "{}\n    {{\"name\": \"{}\", \"cpu\": {}, \"devices\": [{}], \"cycles\": {}, \"overruns\": {}, "
        "\"skipped_cycles\": {}, \"wakeup_latency_us\": {}, \"compute_time_us\": {}}}",
        k ? "," : "", json_text(l.name), l.cpu, fmt::join(quoted(l.devices), ", "), l.statistics.cycles,
        l.statistics.overruns, l.statistics.skipped_cycles, histogram_json(l.statistics.wakeup_latency),
        histogram_json(l.statistics.compute_time));
  }
  out += "\n  ],\n";
  out += fmt::format("  \"recorder\": {{\"records\": {}, \"dropped\": {}, \"lost\": {}, \"failed\": {}}},\n",
                     r.records_written, r.records_dropped, r.records_lost, r.recording_failed);
  if (r.has_round_trip) {
    const RoundTripStatistics& rt = r.round_trip;
    out +=
        fmt::format("  \"dds_round_trip_us\": {{\"count\": {}, \"p50\": {:.3f}, \"p99\": {:.3f}, \"max\": {:.3f}}},\n",
                    rt.count, rt.p50_us, rt.p99_us, rt.max_us);
    out += fmt::format("  \"dds_applied_after_cycles\": [{}],\n", fmt::join(rt.applied_after_cycles, ", "));
  }
  if (r.dds.enabled)
    out += fmt::format(
        "  \"dds\": {{\"deadline_misses\": {}, \"commands_rejected\": {}, \"claims_ended\": {}, "
        "\"log_forwarded\": {}, \"log_suppressed\": {}}},\n",
        r.dds.deadline_misses, r.dds.commands_rejected, r.dds.claims_ended, r.dds.log_forwarded, r.dds.log_suppressed);
  out += "  \"devices\": [";
  for (std::size_t i = 0; i < r.sessions->size(); ++i) {
    const DeviceSession& d = *(*r.sessions)[i];
    out += fmt::format(
        "{}\n    {{\"name\": \"{}\", \"fault\": \"{}\", \"fault_cycle\": {}, \"faults\": {}, \"recoveries\": {}, "
        "\"saturated_cycles\": {}, \"safety_events\": {}}}",
        i ? "," : "", d.name(), d.status().fault() == DeviceFault::none ? "none" : json_text(d.status().fault_text()),
        d.status().fault_cycle(), d.status().faults_raised(), d.status().recoveries(), d.status().saturated_cycles(),
        events_json(r, i));
  }
  out += "\n  ]\n}\n";
  return out;
}

std::vector<std::string> report_lines(const SessionReport& r) {
  const CycleStatistics& s = r.result->statistics;
  std::vector<std::string> lines;
  const std::string loops =
      r.result->loops.size() > 1 ? fmt::format(" over {} loops", r.result->loops.size()) : std::string();
  lines.push_back(fmt::format("{} cycles{} in {:.3f} s loop time ({:.3f} s wall), {} overruns, {} skipped", s.cycles,
                              loops, r.result->loop_time_s, r.result->wall_time_s, s.overruns, s.skipped_cycles));
  if (r.config->server.clock != ClockMode::lockstep)
    lines.push_back("wake-up latency: " + histogram_summary(s.wakeup_latency));
  lines.push_back("compute time:    " + histogram_summary(s.compute_time));
  if (r.result->loops.size() > 1) {
    for (const LoopResult& l : r.result->loops) {
      const double share = l.statistics.cycles ? 100.0 * static_cast<double>(l.statistics.overruns) /
                                                     static_cast<double>(l.statistics.cycles)
                                               : 0.0;
      lines.push_back(fmt::format("loop '{}' ({}; {}): {} cycles, {} overruns ({:.2f} %), {} skipped", l.name,
                                  l.cpu >= 0 ? fmt::format("CPU {}", l.cpu) : std::string("not pinned"),
                                  fmt::join(l.devices, ", "), l.statistics.cycles, l.statistics.overruns, share,
                                  l.statistics.skipped_cycles));
      if (r.config->server.clock != ClockMode::lockstep)
        lines.push_back("  wake-up latency: " + histogram_summary(l.statistics.wakeup_latency));
      lines.push_back("  compute time:    " + histogram_summary(l.statistics.compute_time));
    }
  }
  for (std::size_t i = 0; i < r.sessions->size(); ++i) {
    const DeviceSession& d = *(*r.sessions)[i];
    const std::string saturated = d.status().saturated_cycles()
                                      ? fmt::format(", torque saturated in {} cycles", d.status().saturated_cycles())
                                      : std::string();
    if (d.status().faults_raised() == 0 && d.status().fault() == DeviceFault::none) {
      lines.push_back(fmt::format("device '{}': ok{}", d.name(), saturated));
      continue;
    }
    lines.push_back(fmt::format("device '{}': {} fault{}, {} recover{}; {}{}", d.name(), d.status().faults_raised(),
                                d.status().faults_raised() == 1 ? "" : "s", d.status().recoveries(),
                                d.status().recoveries() == 1 ? "y" : "ies",
                                d.status().fault() == DeviceFault::none
                                    ? std::string("running at the end")
                                    : fmt::format("in its safe mode at the end ({})", fault_code(d.status().fault())),
                                saturated));
    if (r.monitor == nullptr) continue;
    for (const SafetyEvent& e : r.monitor->safety_log(i))
      lines.push_back(fmt::format("  {} {} at cycle {} ({:.3f} s): {}",
                                  e.kind == SafetyEvent::Kind::fault ? "FAULT" : "recovered from", fault_code(e.fault),
                                  e.cycle, static_cast<double>(e.time_ns) * 1e-9, to_string(e.fault)));
    if (const std::uint64_t more = r.monitor->safety_events_not_kept(i) + d.status().lost_safety_events(); more > 0)
      lines.push_back(fmt::format("  ... and {} more faults and recoveries not kept", more));
  }
  if (r.stages == nullptr) return lines;
  for (const auto& stage : *r.stages) {
    for (const auto& g : stage->guards()) {
      if (g->smallest_distance() >= 1e9) continue;  // never measured
      lines.push_back(fmt::format("group '{}': {} / {} closest {:.3f} m, repulsion up to {:.1f} N, {} trip{}",
                                  stage->name(), g->first().name(), g->second().name(), g->smallest_distance(),
                                  g->largest_repulsion_n(), g->trips(), g->trips() == 1 ? "" : "s"));
    }
  }
  return lines;
}

}  // namespace hapticd::server
