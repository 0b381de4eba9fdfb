#include "app/commands.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string_view>
#include <thread>

#include "app/invariant_stop.hpp"
#include "app/served_session.hpp"
#include "app/session_monitor.hpp"
#include "app/session_report.hpp"
#include "app/signals.hpp"
#include "app/startup_checks.hpp"
#include "assembly/session_builder.hpp"
#include "config/config_error.hpp"
#include "config/session_config.hpp"
#include "config/yaml_reader.hpp"
#include "doors/dds/cyclone_log.hpp"
#include "doors/doors.hpp"
#include "executor/executor.hpp"
#include "recorder/recorder.hpp"

namespace hapticd::server {
namespace {

// What a device is, for the log at start and --check-config: "forcedimension omega.6, serial 10001; Force Dimension
// SDK 3.6.0, /opt/.../libdrd.so.3" (a simulation says so).
std::string identity(const DeviceDescription& d) {
  std::string text = d.model;
  if (!d.serial.empty()) text += ", serial " + d.serial;
  if (!d.vendor_software.empty()) text += "; " + d.vendor_software;
  if (d.simulated) text += " (simulated)";
  return text;
}

struct LoadedSession {
  SessionConfig config;
  std::unique_ptr<PluginLoader> loader;
  std::vector<std::unique_ptr<DeviceSession>> sessions;
  std::vector<std::unique_ptr<GroupStage>> stages;
  std::vector<ConfigureFailure> configure_failures;  // devices isolated at start-up (run only)
};

// Config errors are printed once, here, without a log prefix: they are for the user to fix.
// --busy-machine: the loop watchdogs of simulated devices (the shipped sim and playback plugins) loosened to what a
// development machine that compiles or runs tests beside the server keeps (the tests' own: a stall of 1 s, 2000
// overruns in a row); a device of any other plugin - hardware - keeps its settings, and the log says which changed.
void loosen_loop_watchdogs(SessionConfig& config) {
  for (DeviceConfig& d : config.devices) {
    if (d.device.plugin != "sim" && d.device.plugin != "playback") {
      spdlog::info("--busy-machine: device '{}' ({}) is not simulated: its watchdogs stay as set", d.name,
                   d.device.plugin);
      continue;
    }
    if (d.safety.max_stall_s > 0.0) d.safety.max_stall_s = std::max(d.safety.max_stall_s, 1.0);
    if (d.safety.max_consecutive_overruns > 0)
      d.safety.max_consecutive_overruns = std::max<std::uint32_t>(d.safety.max_consecutive_overruns, 2000);
    spdlog::info("--busy-machine: device '{}' (simulated): max_stall_s {} s, max_consecutive_overruns {}", d.name,
                 d.safety.max_stall_s, d.safety.max_consecutive_overruns);
  }
}

// A device that is not there (DeviceUnavailable: its vendor's library or service missing, no device answering):
// exit code 4, nothing powered; `exit_code` says which.
std::optional<LoadedSession> load(const std::string& file, const std::vector<std::string>& sets,
                                  const RunOptions* overrides, int* exit_code = nullptr) {
  LoadedSession s;
  try {
    s.config = load_session_config(file, sets);
    if (overrides != nullptr) {
      if (overrides->duration_s) s.config.server.duration_s = *overrides->duration_s;
      if (overrides->clock) s.config.server.clock = clock_mode(*overrides->clock);
      if (overrides->dds_domain) {
        s.config.dds.enabled = true;
        s.config.dds.domain_id = *overrides->dds_domain;
      }
      if (overrides->busy_machine) loosen_loop_watchdogs(s.config);
    }
    s.loader = std::make_unique<PluginLoader>(PluginLoader::search_paths_for(s.config.server.plugin_paths));
    // Running, a plugin that throws from configure() isolates its device; checking, it is an error.
    s.sessions = build_sessions(s.config, *s.loader, overrides != nullptr ? &s.configure_failures : nullptr);
    s.stages = build_group_stages(s.config, s.sessions, *s.loader);
    return s;
  } catch (const ConfigError& e) {
    fmt::print(stderr, "error: {}{}\n", e.what(), e.device_unavailable() ? "; no device was powered" : "");
    if (exit_code != nullptr) *exit_code = e.device_unavailable() ? kExitRuntimeError : kExitConfigError;
  }
  return std::nullopt;
}

// indent: the keys' indent (a nested mapping's keys stand further in than their parent's).
void print_schema(const ParameterSchema& schema, int indent = 2) {
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  const int width = 26 - indent;
  if (schema.specs().empty()) fmt::print("{}(no parameters)\n", pad);
  for (const auto& spec : schema.specs())
    fmt::print("{}{:<{}} {}\n{}{:<{}}   {}\n", pad, spec.name, width, spec.description, pad, "", width,
               spec.constraints_text());
}

}  // namespace

int check_config(const std::string& file, const std::vector<std::string>& sets) {
  int code = kExitConfigError;
  const auto s = load(file, sets, nullptr, &code);
  if (!s) return code;
  fmt::print("{}: ok ({} device{}, {} Hz, {} clock)\n", file, s->sessions.size(), s->sessions.size() == 1 ? "" : "s",
             s->config.server.rate_hz, clock_name(s->config.server.clock));
  for (const auto& d : s->sessions) {
    fmt::print("  {}: {}\n", d->name(), identity(d->description()));
    const DeviceChain& c = d->chain();
    for (std::size_t k = 0; k < c.schemes.size(); ++k) {
      const SchemeChain& sc = c.schemes[k];
      fmt::print("  {}: {} ({} joints){}{} -> {}   [scheme {}{}]\n", d->name(), c.device.descriptor->name,
                 d->description().dof(),
                 sc.virtual_model ? fmt::format(" -> {}", sc.virtual_model->descriptor->name) : "",
                 sc.inverse_kinematics ? fmt::format(" -> {}", sc.inverse_kinematics->descriptor->name) : "",
                 sc.controller.descriptor->name, sc.name, k == 0 ? ", at start" : "");
    }
  }
  for (const auto& g : s->stages) {
    std::string names;
    for (const DeviceSession* d : g->devices()) names += (names.empty() ? "" : ", ") + d->name();
    fmt::print("  group {}: {}; {} pair(s) with collision capsules\n", g->name(), names, g->guards().size());
  }
  if (const TeleoperationSettings& t = s->config.teleoperation; t.enabled)
    fmt::print("  teleoperation: {} is the {} of '{}' on DDS domain {} ({}{}, passivity {}; link lost after {} s)\n",
               t.device, t.role == teleop::Role::master ? "master" : "remote", t.peer, s->config.dds.domain_id,
               teleop::to_string(t.link.architecture), t.link.rotation ? " in six degrees of freedom" : "",
               teleop::to_string(t.link.passivity), t.link.link_timeout_s);
  return kExitOk;
}

int run_session(const RunOptions& options) {
  int code = kExitConfigError;
  auto s = load(options.config_file, options.sets, &options, &code);
  if (!s) return code;
  const ServerSettings& server = s->config.server;
  const bool lockstep = server.clock == ClockMode::lockstep;
  if (lockstep && server.duration_s <= 0.0)
    spdlog::warn("lockstep clock without a duration: the session runs as fast as possible until SIGINT/SIGTERM");
  for (const std::string& w : s->config.warnings) spdlog::warn("safety: {}", w);

  // The stacks the threads still to come reserve (loop, recorder, gate; Cyclone creates its own with smaller
  // stacks), and 8 MB of working memory: calibrated with ulimit -v (docs/safety.md).
  const int threads = (s->config.dds.enabled || s->config.engine_socket.enabled ? 6 : 3) +
                      (s->config.live_view.enabled ? 1 : 0) + (s->config.engine_socket.enabled ? 1 : 0);
  if (const std::string missing = check_address_space(threads, 8u << 20); !missing.empty()) {
    spdlog::error("cannot start the session: {}; no device was powered", missing);
    return kExitRuntimeError;
  }

  std::vector<DeviceSession*> sessions;
  for (const auto& d : s->sessions) sessions.push_back(d.get());
  const std::atomic<bool>& stop = install_stop_signal_handlers();
  install_invariant_stop(stop_flag());  // a broken invariant off the loop: a safe stop, exit code 4 (no abort)
  std::unique_ptr<ServedSession> served;
  try {  // before any device is powered
    std::vector<GroupStage*> stages;
    for (const auto& g : s->stages) stages.push_back(g.get());
    served = std::make_unique<ServedSession>(s->config, sessions, std::move(stages),
                                             ServeOptions{options.record_file, /*realtime_setup=*/true, &stop});
  } catch (const std::exception& e) {
    spdlog::error("{}; no device was powered", e.what());
    return kExitRuntimeError;
  }
  Doors* doors = served->doors();
  Recorder* recorder = served->recorder();
  if (doors != nullptr && doors->dds() != nullptr) {
    std::string cpus;
    for (int c : served->dds_cpus()) cpus += (cpus.empty() ? "" : ",") + std::to_string(c);
    spdlog::info("DDS interface on domain {} ({}){}", s->config.dds.domain_id,
                 dds::describe_network({s->config.dds.domain_id, s->config.dds.cyclone_config, s->config.dds.network}),
                 cpus.empty() ? std::string()
                              : fmt::format(", DDS threads on CPU {}, the loop on CPU {}", cpus, served->loop_cpu()));
  }

  if (const live_view::LiveView* view = served->live_view()) {
    {
      std::string page = view->url();
      if (page.rfind("ws://", 0) == 0) page = "http://" + page.substr(5) + "/";
      spdlog::info(
          "live view on {} (the page: {} in a browser; Foxglove or Lichtblick: the ws:// address; "
          "docs/live-view.md)",
          view->url(), page);
    }
    if (s->config.live_view.address != "127.0.0.1" && s->config.live_view.address != "::1")
      spdlog::warn("the live view listens on {}, not on loopback only: whoever reaches it can watch the session",
                   s->config.live_view.address);
  }

  if (doors != nullptr)
    if (const EngineSocket* socket = doors->engine_socket()) {
      spdlog::info("engine socket on {} (WebSocket/JSON for engines without DDS; docs/engine-socket.md){}",
                   socket->url(), s->config.engine_socket.token.empty() ? "" : ", token required");
      if (!net::loopback_address(s->config.engine_socket.address))
        spdlog::warn("the engine socket listens on {}, beyond this machine: only clients with its token may connect",
                     s->config.engine_socket.address);
    }

  if (doors != nullptr && doors->ros2() != nullptr)
    spdlog::info(
        "ROS 2 topics in ROS domain {} at {} Hz: {}/<device>/pose, twist, wrench, joint_states or buttons, "
        "robot_description; /tf (docs/ros2.md)",
        s->config.ros2.domain_id, s->config.ros2.rate_hz, s->config.ros2.ns);

  for (const ConfigureFailure& f : s->configure_failures)
    spdlog::error("device '{}' {}: {}", f.device,
                  f.powered ? "is held in its safe state (zero torque)" : "is left out (its drives stay unpowered)",
                  f.error.what());

  spdlog::info("session {}: {} device(s) at {} Hz, {} clock{}", options.config_file, sessions.size(), server.rate_hz,
               clock_name(server.clock),
               server.duration_s > 0 ? fmt::format(", {} s", server.duration_s) : std::string(", until stopped"));
  for (const DeviceSession* d : sessions) spdlog::info("device '{}': {}", d->name(), identity(d->description()));

  ExecutorResult result;
  try {
    result = served->run(stop);
  } catch (const std::bad_alloc&) {
    spdlog::error("session failed: out of memory (no device was left powered)");
    return kExitRuntimeError;
  } catch (const std::exception& e) {
    spdlog::error("session failed: {} (no device was left powered)", e.what());
    return kExitRuntimeError;
  }
  const std::optional<std::string> broken = invariant_failure();
  if (broken)
    spdlog::error(
        "internal invariant failed: {}; this is a bug, please report it; every device was stopped through "
        "its safe mode",
        *broken);
  for (const auto& w : result.warnings) spdlog::warn("{}", w);
  for (const auto& e : result.plugin_errors) spdlog::error("{}", e);
  if (doors != nullptr) {
    for (std::size_t i = 0; i < sessions.size(); ++i) {
      spdlog::info("{}: engine commands accepted {}, rejected {}, deadline misses {}", sessions[i]->name(),
                   doors->commands_accepted(i), doors->commands_rejected(i), doors->deadline_misses(i));
    }
    if (const TeleopLink* link = doors->teleop_link(); link != nullptr) {
      const TeleopLink::Energy e = link->energy();
      spdlog::info(
          "{}: teleoperation link to '{}': packets sent {}, taken {}, rejected {}; lost {} times, {} stops; energy in "
          "{:.4f} J, out {:.4f} J, dissipated {:.4f} J, lowest observed {:.4f} J; largest force {:.2f} N",
          link->settings().device, link->settings().peer, link->packets_sent(), link->packets_taken(),
          link->packets_rejected(), link->losses(), link->stops(), e.in, e.out, e.dissipated, e.lowest_observed,
          e.max_force_n);
      if (link->settings().link.rotation)
        spdlog::info(
            "{}: teleoperation link in rotation: largest torque {:.3f} N m (the energies above count rotation's "
            "port too)",
            link->settings().device, e.max_torque_n_m);
      spdlog::info(
          "{}: teleoperation link's peer: bound {} times; {} packets rejected from another participant than the bound "
          "peer; its energy in claimed {:.4f} J, credited {:.4f} J (what its force and motion could carry)",
          link->settings().device, link->bindings(), link->impostor_packets(), e.peer_claimed, e.peer_credited);
      const TeleopLink::Delay d = link->delay();
      if (d.valid) {
        spdlog::info(
            "{}: teleoperation link's delay, measured: one-way to this side {:.2f} ms, from it {:.2f} ms (means); "
            "round trip {:.2f} ms (the shortest of the last 2 s); the peer's clock {:+.3f} ms from this one's; {} "
            "exchanges, {} refused",
            link->settings().device, 1e3 * d.mean_in_s, 1e3 * d.mean_out_s, 1e3 * d.round_trip_s, 1e3 * d.offset_s,
            d.samples, d.refused);
      } else {
        spdlog::info("{}: teleoperation link's delay: not measured (no exchange with the peer; {} refused)",
                     link->settings().device, d.refused);
      }
    }
    if (const Ros2Door* ros = doors->ros2(); ros != nullptr) {
      for (std::size_t i = 0; i < sessions.size(); ++i)
        spdlog::info("{}: ROS 2 states published {}", sessions[i]->name(), ros->published(i));
      spdlog::info("ROS 2 commands received {}, refused for an unknown frame {}", ros->commands().received(),
                   ros->commands().refused_frames());
      if (const std::uint64_t failed = ros->write_failures(); failed > 0)
        spdlog::warn("{} writes of ROS 2 topics failed (Cyclone refused them: see its messages above)", failed);
    }
    if (const std::uint64_t unknown = doors->unknown_device_commands(); unknown > 0)
      spdlog::warn("{} engine commands named a device this server does not have: rejected as malformed", unknown);
    if (const std::uint64_t unknown = doors->unknown_device_requests(); unknown > 0)
      spdlog::info("{} requests named a device this server does not have: left to the server that has it", unknown);
    if (const std::uint64_t ended = doors->claims_ended(); ended > 0)
      spdlog::info("{} claims ended because their claimant was gone", ended);
    const RoundTripStatistics rt = doors->round_trip();
    if (rt.count > 0) {
      spdlog::info(
          "round trip state -> engine -> command accepted: {} samples, p50 {:.1f} us, p99 {:.1f} us, max {:.1f} us",
          rt.count, rt.p50_us, rt.p99_us, rt.max_us);
      if (const std::uint64_t applied = rt.applied(); applied > 0)
        spdlog::info("commands applied in the cycle after their state's: {} of {} ({:.2f} %), later: {}",
                     rt.applied_after_cycles[1], applied,
                     100.0 * static_cast<double>(rt.applied_after_cycles[1]) / static_cast<double>(applied),
                     applied - rt.applied_after_cycles[1] - rt.applied_after_cycles[0]);
    }
  }

  SessionReport report;
  report.config = &s->config;
  report.result = &result;
  report.sessions = &s->sessions;
  report.stages = &s->stages;
  report.monitor = &served->monitor();
  const auto recording_counts = [&] {
    report.records_written = recorder ? recorder->written() : 0;
    report.records_dropped = recorder ? recorder->dropped() : 0;
    report.records_lost = recorder ? recorder->lost() : 0;
    report.recording_failed = recorder && recorder->failed();
  };
  recording_counts();
  if (doors) {
    report.round_trip = doors->round_trip();
    report.has_round_trip = report.round_trip.count > 0;
    report.dds.enabled = doors->dds() != nullptr;
    for (std::size_t i = 0; i < sessions.size(); ++i) {
      report.dds.deadline_misses += doors->deadline_misses(i);
      report.dds.commands_rejected += doors->commands_rejected(i);
    }
    report.dds.commands_rejected += doors->unknown_device_commands();
    report.dds.claims_ended = doors->claims_ended();
    const cyclone_log::Counts log = cyclone_log::counts();
    report.dds.log_forwarded = log.forwarded;
    report.dds.log_suppressed = log.suppressed;
  }
  if (recorder) {  // the session's statistics and safety events end the recording
    std::vector<RecordingEvent> events;
    for (std::size_t i = 0; i < sessions.size(); ++i)
      for (const SafetyEvent& e : served->monitor().safety_log(i))
        events.push_back({sessions[i]->name(), e.kind == SafetyEvent::Kind::fault ? "fault" : "recovery",
                          std::string(fault_code(e.fault)), e.cycle, static_cast<double>(e.time_ns) * 1e-9});
    if (recorder->failed())  // the recording's own loss, in the file it concerns: device "", cycle = records kept
      events.push_back({"", "recording_failed", "lost " + std::to_string(recorder->lost()) + " device-cycles",
                        recorder->written(), result.loop_time_s});
    recorder->close(report_json(report), events);
    recording_counts();
  }
  for (const auto& line : report_lines(report)) spdlog::info("{}", line);
  if (const live_view::LiveView* view = served->live_view()) {
    const auto& c = view->counters();
    spdlog::info(
        "live view: {} viewer(s) connected, {} refused, {} messages sent, {} dropped (slow viewers), {} bad "
        "requests, {} disconnected (slow, not reading or idle)",
        c.connections.load(), c.refused.load(), c.sent.load(), c.dropped.load(), c.bad_requests.load(),
        c.disconnected.load());
  }
  if (recorder) {
    if (recorder->failed()) {
      spdlog::error("recording FAILED: {}; {} device-cycles in {} (whole records), {} lost, {} dropped",
                    recorder->error(), recorder->written(), options.record_file, recorder->lost(), recorder->dropped());
    } else {
      spdlog::info("recorded {} device-cycles to {} ({} dropped)", recorder->written(), options.record_file,
                   recorder->dropped());
    }
  }
  if (!options.stats_json.empty()) {
    std::ofstream out(options.stats_json);
    out << report_json(report);
    if (!out) {
      spdlog::error("cannot write {}", options.stats_json);
      return kExitRuntimeError;
    }
  }
  if (broken) {
    // The thread that failed is waiting in the handler: leave without the destructors that would join it.
    spdlog::default_logger()->flush();
    std::fflush(stdout);
    std::_Exit(kExitRuntimeError);
  }
  if (any_device_faulted(report)) return kExitDeviceFault;
  if (!result.plugin_errors.empty() || served->monitor().plugin_errors() > 0) return kExitRuntimeError;
  return recorder && recorder->failed() ? kExitRecordingFailed : kExitOk;
}

int list_plugins(const std::string& config_file) {
  std::vector<std::filesystem::path> configured;
  if (!config_file.empty()) {
    try {
      configured = load_session_config(config_file).server.plugin_paths;
    } catch (const ConfigError& e) {
      fmt::print(stderr, "error: {}\n", e.what());
      return kExitConfigError;
    }
  }
  PluginLoader loader(PluginLoader::search_paths_for(configured));
  std::vector<std::string> problems;
  const auto handles = loader.list_all(&problems);
  // Columns as wide as their longest entry (a plugin's name may be long: out-of-tree plugins prefix theirs).
  std::size_t name_width = 4, kind_width = 4, version_width = 7;
  for (const auto& h : handles) {
    name_width = std::max(name_width, std::string_view(h.descriptor->name).size());
    kind_width = std::max(kind_width, std::string_view(to_string(h.descriptor->kind)).size());
    version_width = std::max(version_width, std::string_view(h.descriptor->version).size());
  }
  if (!handles.empty())
    fmt::print("{:<{}}  {:<{}}  {:<{}}  {}  ({})\n", "name", name_width, "kind", kind_width, "version", version_width,
               "summary", "library");
  for (const auto& h : handles)
    fmt::print("{:<{}}  {:<{}}  {:<{}}  {}  ({})\n", h.descriptor->name, name_width, to_string(h.descriptor->kind),
               kind_width, h.descriptor->version, version_width, h.descriptor->summary, h.library->path.string());
  for (const auto& p : problems) fmt::print(stderr, "warning: {}\n", p);
  if (handles.empty()) {
    std::string paths;
    for (const auto& p : loader.search_paths()) paths += (paths.empty() ? "" : ", ") + p.string();
    fmt::print(stderr, "no plugins found; search paths: {}\n", paths);
  }
  return kExitOk;
}

int describe_plugin(const std::string& name, const std::string& config_file) {
  std::vector<std::filesystem::path> configured;
  if (!config_file.empty()) configured = load_session_config(config_file).server.plugin_paths;
  PluginLoader loader(PluginLoader::search_paths_for(configured));
  std::vector<std::string> names;
  for (const auto& h : loader.list_all()) {
    names.emplace_back(h.descriptor->name);
    if (name != h.descriptor->name) continue;
    fmt::print("{} {} ({} plugin): {}\nlibrary: {}\nparameters:\n", h.descriptor->name, h.descriptor->version,
               to_string(h.descriptor->kind), h.descriptor->summary, h.library->path.string());
    print_schema(h.descriptor->parameter_schema());
    return kExitOk;
  }
  const std::string guess = closest_match(name, names);
  fmt::print(stderr, "error: no plugin named '{}' on the search paths{}\n", name,
             guess.empty() ? std::string(" (hapticd --list-plugins lists them)") : " (did you mean '" + guess + "'?)");
  return kExitConfigError;
}

int describe_config(const std::string& config_file) {
  if (!config_file.empty()) {
    // The file's own values first (validated as a session would be), then what every key means.
    const SessionConfig c = load_session_config(config_file);
    fmt::print("{}: {} Hz, {} clock, duration {}; DDS {}\n", config_file, c.server.rate_hz, clock_name(c.server.clock),
               c.server.duration_s > 0 ? fmt::format("{} s", c.server.duration_s) : std::string("until stopped"),
               c.dds.enabled ? fmt::format("on domain {}", c.dds.domain_id) : std::string("off"));
    for (const DeviceConfig& d : c.devices) {
      fmt::print("  device '{}': {}, scheme '{}' ({}{}{}){}\n", d.name, d.device.plugin, d.scheme,
                 d.virtual_model ? d.virtual_model->plugin + " -> " : "",
                 d.inverse_kinematics ? d.inverse_kinematics->plugin + " -> " : "", d.controller.plugin,
                 d.alternatives.empty() ? "" : fmt::format(" and {} more", d.alternatives.size()));
      fmt::print("    switch_ramp_s {}, engine_deadline_s {}, engine_fade_s {}, engine_ramp_in_s {}\n", d.switch_ramp_s,
                 d.engine_deadline_s, d.engine_fade_s, d.engine_ramp_in_s);
      const Eigen::Vector3d rpy = d.base_pose.orientation.toRotationMatrix().eulerAngles(2, 1, 0).reverse();
      fmt::print("    base_pose xyz [{}, {}, {}] m, rpy [{:.4f}, {:.4f}, {:.4f}] rad\n", d.base_pose.position.x(),
                 d.base_pose.position.y(), d.base_pose.position.z(), rpy.x(), rpy.y(), rpy.z());
    }
    fmt::print("\n");
  }
  fmt::print("server section of a session file:\n");
  print_schema(server_settings_schema());
  fmt::print("  {:<24} {}\n  {:<24}   {}\n", "plugin_paths",
             "folders searched for plugin libraries before "
             "HAPTICD_PLUGIN_PATH and the installed plugin folder",
             "", "list of folders, relative to the session file");
  fmt::print("\ndds section of a session file (present: the DDS interface runs):\n");
  print_schema(dds_settings_schema());
  fmt::print(
      "\ngate section (what every door's commands must satisfy, claims, states, lockstep; a session without it "
      "may give these keys in its dds section):\n");
  print_schema(gate_settings_schema());
  fmt::print("\nlive_view section (present: the Foxglove WebSocket live view runs; docs/live-view.md):\n");
  print_schema(live_view_settings_schema());
  fmt::print(
      "\nengine_socket section (present: the WebSocket/JSON door for engines without DDS; docs/engine-socket.md):\n");
  print_schema(engine_socket_settings_schema());
  fmt::print("  {:<24} {}\n", "allowed_origins",
             "web pages (scheme://host[:port]) that may connect besides this machine's");
  fmt::print(
      "\nteleoperation section (present: this device is one side of a link to another server's; "
      "docs/teleoperation.md):\n");
  print_schema(teleoperation_settings_schema());
  fmt::print(
      "\nros2 section (present: the devices on ROS 2's topics and types: pose, twist, wrench, joint states, buttons, "
      "TF, robot description; docs/ros2.md):\n");
  print_schema(ros2_settings_schema());
  fmt::print("  {:<24} {}\n", "commands",
             "the devices given to ROS 2 (claimed by it for the session; wrench_command and pose_command)");
  fmt::print(
      "\nscene section (present: the session's haptic scene, which its devices' haptic_scene models that name no "
      "file render and engines edit at run time; docs/haptic-scene.md):\n");
  fmt::print("  {:<24} {}\n", "plugin", "the scene's plugin (default session_scene)");
  fmt::print("  {:<24} {}\n", "parameters",
             "its parameters (session_scene: file, the scene file; hapticd --describe-plugin session_scene)");
  fmt::print("\na device entry (devices: [...]):\n");
  for (const EntryKey& k : device_entry_keys()) fmt::print("  {:<24} {}\n", k.key, k.text);
  fmt::print("\ngroups (optional, top level; docs/multi-device.md): a list of\n");
  fmt::print("  {:<24} {}\n", "name", "the group's name (1-31 letters, digits, '_', '-')");
  fmt::print("  {:<24} {}\n", "devices", "its devices by name (each in one group at most)");
  fmt::print("  {:<24} {}\n", "min_distance_m",
             "hard minimum clearance between any two of its devices' collision capsules: below it both enter "
             "their safe mode (0 .. 1, default 0: measured, never tripped)");
  fmt::print("  {:<24} {}\n", "repulsion", "a spring-damper between the arms' nearest points, felt on the handles:");
  print_schema(repulsion_schema(), 4);
  fmt::print("  {:<24} {}\n", "loop",
             "present: the group runs on a loop thread of its own (real time; in lockstep all loops run on one "
             "thread), else on the session's loop:");
  print_schema(group_loop_schema(), 4);
  fmt::print("\nbase_pose of a device entry (docs/configuration.md):\n");
  print_schema(base_pose_schema());
  fmt::print("\nsafety section of a device entry (docs/safety.md):\n");
  print_schema(safety_settings_schema());
  return kExitOk;
}

}  // namespace hapticd::server
