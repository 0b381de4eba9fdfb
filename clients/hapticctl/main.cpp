// hapticctl: the command-line client of hapticd's DDS interface (docs/dds-interface.md).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <thread>

#include "hapticd/client/client.hpp"
#include "hapticd/recording/recording_export.hpp"
#include "hapticd/recording/recording_file.hpp"
#include "state_recording.hpp"

namespace {

using hapticd::client::Client;
using hapticd::client::Reply;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }

// As the watch line has always shown it: the safe mode in capitals.
std::string_view mode_name(hapticd::client::Mode m) {
  return m == hapticd::client::Mode::safe ? "SAFE" : hapticd::client::to_string(m);
}

// "torque_saturated,engine_active", or "-".
std::string flags_text(std::uint32_t flags) {
  const std::vector<std::string> names = hapticd::client::flag_names(flags);
  return names.empty() ? std::string("-") : fmt::format("{}", fmt::join(names, ","));
}

void print_state(const hapticd::client::DeviceState& s) {
  fmt::print(
      "{} t={:8.3f} {:<8} scheme {:<22} owner {:<14} pos ({:+.4f} {:+.4f} {:+.4f}) m  F_op ({:+6.2f} {:+6.2f} "
      "{:+6.2f}) N  F_env ({:+6.2f} {:+6.2f} {:+6.2f}) N  flags {}\n",
      s.device.view(), s.time_s(), mode_name(s.mode), s.scheme.view(), s.owner.empty() ? "-" : s.owner.view(),
      s.pose.position[0], s.pose.position[1], s.pose.position[2], s.operator_wrench.force[0],
      s.operator_wrench.force[1], s.operator_wrench.force[2], s.environment_wrench.force[0],
      s.environment_wrench.force[1], s.environment_wrench.force[2], flags_text(s.flags));
  // A handle device's buttons and gripper (docs/devices.md), when there are any to show.
  if (s.buttons != 0 || s.gripper != 0.0) fmt::print("  buttons {:#x} gripper {:.3f} rad\n", s.buttons, s.gripper);
}

// "vishard3 event mode: safe", and the message when it says more than the code.
void print_event(const hapticd::client::Event& e) {
  const std::string kind(to_string(e.kind));
  const bool says_more = !e.message.empty() && e.message != e.code && e.message != kind + ": " + e.code;
  fmt::print("{} event {}: {}{}{}\n", e.device, kind, e.code.empty() ? "-" : e.code, says_more ? " - " : "",
             says_more ? e.message : "");
}

// hapticctl export: every (or the named) device's cycles as CSV beside the recording (or in out_dir).
int export_recording(const std::string& recording, std::vector<std::string> devices,
                     const std::vector<std::string>& exclude, const std::string& out_dir) {
  try {
    const std::vector<std::string> recorded = hapticd::recording::recorded_devices(recording);
    if (devices.empty()) devices = recorded;
    const std::filesystem::path source(recording);
    const std::filesystem::path dir = out_dir.empty() ? source.parent_path() : std::filesystem::path(out_dir);
    if (!out_dir.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(dir, ec);
      if (ec) {
        fmt::print(stderr, "hapticctl export: cannot create the folder {}: {}\n", dir.string(), ec.message());
        return 2;
      }
    }
    for (const std::string& d : devices) {
      const std::filesystem::path target = dir / (source.stem().string() + "." + d + ".csv");
      std::ofstream out(target);
      if (!out) {
        fmt::print(stderr, "hapticctl export: cannot write {}: {}\n", target.string(), std::strerror(errno));
        return 2;
      }
      const std::size_t rows = hapticd::recording::export_csv(recording, d, out, exclude);
      out.close();
      if (!out) {
        fmt::print(stderr, "hapticctl export: cannot write {}: {}\n", target.string(), std::strerror(errno));
        return 2;
      }
      fmt::print("{}: {} cycles of '{}'\n", target.string(), rows, d);
    }
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "hapticctl export: {}\n", e.what());
    return 2;
  }
}

// A cycle record's flags (their own bits: 1 torque saturated, 2 limit engaged, 4 render limited, 8 thermal).
std::string record_flags(std::uint32_t flags) {
  static constexpr std::array<const char*, 4> kNames = {"torque_saturated", "limit_engaged", "render_limited",
                                                        "thermal_derating"};
  std::string out;
  for (std::size_t bit = 0; bit < kNames.size(); ++bit)
    if ((flags & (1u << bit)) != 0) out += (out.empty() ? "" : ",") + std::string(kNames[bit]);
  return out.empty() ? "-" : out;
}

void print_fault_report(const hapticd::client::FaultReport& r, bool earlier) {
  fmt::print("{} fault report {}{}: {} at cycle {} ({}), {} cycles of history:\n", r.device, r.serial,
             earlier ? " (from before this watch)" : "", r.fault, r.cycle, r.message, r.records.size());
  for (std::size_t k = r.records.size() > 5 ? r.records.size() - 5 : 0; k < r.records.size(); ++k) {
    const hapticd::client::CycleRecord& c = r.records[k];
    fmt::print(
        "{}   cycle {:>8}  pos ({:+.4f} {:+.4f} {:+.4f}) m  vel ({:+.3f} {:+.3f} {:+.3f}) m/s  F_op ({:+6.2f} "
        "{:+6.2f} {:+6.2f}) N  flags {}\n",
        r.device, c.cycle, c.handle_position[0], c.handle_position[1], c.handle_position[2], c.handle_velocity[0],
        c.handle_velocity[1], c.handle_velocity[2], c.operator_force[0], c.operator_force[1], c.operator_force[2],
        record_flags(c.flags));
  }
}

std::string unit_suffix(const hapticd::ParameterInfo& p) { return p.unit.empty() ? "" : " " + p.unit; }

// hapticctl get: "controller.kp = 500 N/m", then its type, bounds and tunability, and what it is.
void print_parameter(const hapticd::ParameterInfo& p) {
  fmt::print("{} = {}{}\n  {}; bounds {}; {}\n", p.name, p.value_text, unit_suffix(p), to_string(p.type),
             p.bounds_text(), p.tunable ? "tunable at run time" : "fixed while the device runs");
  if (!p.description.empty()) fmt::print("  {}\n", p.description);
}

// hapticctl params: one line per parameter, in columns.
void print_parameter_table(const std::vector<hapticd::ParameterInfo>& parameters) {
  std::size_t name = 4, value = 5, unit = 4, bounds = 6;
  for (const auto& p : parameters) {
    name = std::max(name, p.name.size());
    value = std::max(value, p.value_text.size());
    unit = std::max(unit, p.unit.size());
    bounds = std::max(bounds, p.bounds_text().size());
  }
  fmt::print("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {:<7}  {}\n", "NAME", name, "VALUE", value, "UNIT", unit, "BOUNDS",
             bounds, "TUNABLE", "DESCRIPTION");
  for (const auto& p : parameters)
    fmt::print("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {:<7}  {}\n", p.name, name, p.value_text, value,
               p.unit.empty() ? "-" : p.unit, unit, p.bounds_text(), bounds, p.tunable ? "yes" : "no", p.description);
}

int report(const Reply& r) {
  if (!r.answered) {
    fmt::print(stderr, "no reply: {}\n", r.message);
    return 3;
  }
  fmt::print("{}: {}\n", r.accepted ? "accepted" : "refused", r.message);
  return r.accepted ? 0 : 1;
}

// Until the duration (0: until Ctrl-C), calling `tick` every 20 ms; false when interrupted.
bool run_for(double duration_s, const std::function<void()>& tick = {}) {
  const auto start = std::chrono::steady_clock::now();
  while (!g_stop.load()) {
    if (duration_s > 0.0 && std::chrono::steady_clock::now() - start > std::chrono::duration<double>(duration_s))
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (tick) tick();
  }
  return false;
}

// hapticctl record: every state the device publishes until the duration or Ctrl-C, in the recording format.
int record_states(Client& client, const std::string& device, const std::string& file, double duration,
                  std::chrono::duration<double> wait) {
  const std::optional<hapticd::client::DeviceInfo> info = client.wait_for_device(device, wait);
  if (!info) {
    fmt::print(stderr, "no description of '{}'\n", device);
    return 2;
  }
  // Shared with the callback: a state callback already running when it is unset still has the recording.
  std::shared_ptr<hapticd::ctl::StateRecording> recording;
  try {
    recording = std::make_shared<hapticd::ctl::StateRecording>(file, *info);
    client.on_state([recording, device](const hapticd::client::DeviceState& s) {
      if (s.device == device) recording->add(s);
    });
    run_for(duration, [&] { recording->write(); });
    client.on_state({});
    recording->close();
    fmt::print("recorded {} states of '{}' to {}\n", recording->states(), device, file);
    return recording->states() > 0 ? 0 : 1;
  } catch (const std::exception& e) {
    client.on_state({});
    fmt::print(stderr, "hapticctl record: {}\n", e.what());
    return 2;
  }
}

}  // namespace

namespace {
int run(int argc, char** argv) {
  CLI::App app{"hapticctl: list, watch and command hapticd devices over DDS (loopback-only by default)"};
  app.require_subcommand(1);
  app.fallthrough();                                // the options before or after the subcommand
  app.option_defaults()->always_capture_default();  // help shows the defaults
  int domain = 0;
  std::string id = "hapticctl", cyclone;
  double timeout = 2.0;
  app.add_option("--domain", domain, "DDS domain (else HAPTICD_DOMAIN)")
      ->envname("HAPTICD_DOMAIN")
      ->check(CLI::Range(0, 230));
  app.add_option("--id", id, "client id (the owner name of a claim)");
  std::string network;
  app.add_option("--cyclone-config", cyclone, "Cyclone DDS XML (default: the built-in loopback configuration)");
  app.add_option("--network", network,
                 "the network instead: interfaces=NAME|ADDRESS,...;peers=ADDRESS,...;multicast=false (default: "
                 "HAPTICD_DDS_NETWORK, else loopback only)");
  app.add_option("--timeout", timeout, "seconds to wait for devices and replies");

  std::string device, scheme, parameter, file, what;
  std::vector<double> values;
  double duration = 0.0, rate = 10.0;

  std::string group;
  bool all = false;
  auto* list = app.add_subcommand("list", "list the devices the servers on this domain describe");
  auto* groups = app.add_subcommand("groups", "list the device groups the servers on this domain describe");
  auto* watch = app.add_subcommand("watch", "print a device's state live, and its events");
  watch->add_option("device", device, "device name")->required();
  watch->add_option("--rate", rate, "lines per second")->check(CLI::Range(0.1, 1000.0));
  watch->add_option("--duration", duration, "stop after this many seconds");
  double hold = 0.0;
  // A device, or with --group every device of a group (claim: all or none), or with --all every device; exactly
  // one of them (checked after parsing).
  std::vector<CLI::App*> targeted;
  const auto target = [&](CLI::App* command, bool with_all) {
    auto* d = command->add_option("device", device, "device name");
    auto* g = command->add_option("--group", group, "every device of this group");
    d->excludes(g);
    if (with_all)
      command->add_flag("--all", all, "every device of every server on the domain")->excludes(d)->excludes(g);
    targeted.push_back(command);
  };
  auto* claim = app.add_subcommand(
      "claim", "claim a device or a group's devices, all or none (as --id); a claim ends with the process");
  target(claim, false);
  claim->add_option("--hold", hold, "keep the claim this many seconds (until Ctrl-C with -1), then release it")
      ->check(CLI::Range(-1.0, 1e6));
  auto* release = app.add_subcommand("release", "release a device this process claimed (useful with --hold only)");
  target(release, false);
  auto* switch_cmd = app.add_subcommand("scheme", "switch a device's control scheme");
  switch_cmd->add_option("device", device)->required();
  switch_cmd->add_option("scheme", scheme)->required();
  auto* set = app.add_subcommand("set", "set a run-time parameter: <stage>.<name> values...");
  set->add_option("device", device)->required();
  set->add_option("parameter", parameter, "e.g. virtual_model.mass_kg")->required();
  set->add_option("values", values)->required();
  auto* get = app.add_subcommand(
      "get", "read a parameter: <stage>.<name>; its value in effect, unit, type, bounds and run-time tunability");
  get->add_option("device", device)->required();
  get->add_option("parameter", parameter, "e.g. controller.force_gain")->required();
  auto* params = app.add_subcommand(
      "params", "list a device's parameters: name, value in effect, unit, bounds, run-time tunable, description");
  params->add_option("device", device)->required();
  bool tunable_only = false;
  std::string stage_filter;
  params->add_flag("--tunable", tunable_only, "only those tunable at run time");
  params->add_option("--stage", stage_filter, "only this stage's")
      ->check(CLI::IsMember({"device", "virtual_model", "controller", "safety"}));
  auto* record = app.add_subcommand(
      "record", "record a device's published states to HDF5, the server's recording format (docs/recording.md)");
  record->add_option("device", device)->required();
  record->add_option("file", file, "the recording (.h5; hapticctl export FILE --csv for CSV)")
      ->required()
      ->check(CLI::Validator([](const std::string& f) { return hapticd::recording::recording_name_problem(f); },
                             "FILE.h5"));
  record->add_option("--duration", duration, "seconds (default: until Ctrl-C)");
  auto* export_cmd = app.add_subcommand(
      "export", "a recording (hapticd --record, HDF5) as CSV: one file per device, FILE's name with .DEVICE.csv");
  std::string recording;
  bool csv = false;
  std::vector<std::string> export_devices, exclude;
  std::string out_dir;
  export_cmd->add_option("file", recording, "the recording (.h5)")->required();
  export_cmd->add_flag("--csv", csv, "CSV (the one format there is; required, for clarity)")->required();
  export_cmd->add_option("--device", export_devices, "only these devices (default: every one)");
  export_cmd->add_option("--exclude", exclude, "leave out these datasets or groups, e.g. timing");
  export_cmd->add_option("--out", out_dir, "folder of the CSV files (default: the recording's)");
  auto* estop = app.add_subcommand(
      "estop", "emergency stop: the device (--group: each of the group's, --all: every one) goes to its safe mode");
  target(estop, true);
  auto* recover = app.add_subcommand(
      "recover", "leave the safe mode after a fault or an E-stop (--group / --all: every device or none)");
  target(recover, true);
  auto* op = app.add_subcommand(
      "operator",
      "drive a simulated device's operator: push FX FY FZ [RAMP_S] | move DX DY DZ [DURATION_S] | release | grasp G");
  op->add_option("device", device)->required();
  op->add_option("command", what)->required()->check(CLI::IsMember({"push", "move", "release", "grasp"}));
  op->add_option("values", values);
  CLI11_PARSE(app, argc, argv);
  if (std::getenv("HAPTICD_PARSE_ONLY") != nullptr) {  // the documentation's commands test (docs_commands)
    std::fputs("hapticctl: the command line parsed (HAPTICD_PARSE_ONLY is set: nothing run)\n", stderr);
    return 0;
  }
  for (CLI::App* command : targeted)
    if (command->parsed() && device.empty() && group.empty() && !all) {
      fmt::print(stderr, "{}: name a device, or --group GROUP{}\n", command->get_name(),
                 command->get_option_no_throw("--all") != nullptr ? ", or --all" : "");
      return 106;  // CLI11's code for a missing argument
    }
  if (*export_cmd) return export_recording(recording, export_devices, exclude, out_dir);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  hapticd::client::ClientOptions options(id, domain);
  options.cyclone_config = cyclone;
  options.network = network;
  Client client(options);
  const auto wait = std::chrono::duration<double>(timeout);

  if (*list) {
    // Until a first description arrives, then a moment for the other servers' (each sends its own).
    const auto give_up = std::chrono::steady_clock::now() + wait;
    while (client.devices().empty() && std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto devices = client.devices();
    if (devices.empty()) {
      fmt::print("no devices on domain {}\n", domain);
      return 1;
    }
    for (const auto& d : devices) {
      std::string schemes;
      for (const auto& s : d.schemes) schemes += (schemes.empty() ? "" : ", ") + s.name;
      const auto& base = d.base_pose;
      fmt::print(
          "{:<16} {} joints, {} ({}), {} Hz, schemes: {}; engine deadline {} ms; base at [{}, {}, {}] m, "
          "orientation [{}, {}, {}, {}]\n",
          d.device, d.dof, d.device_plugin, d.simulated ? "simulated" : "hardware", d.rate_hz, schemes,
          1e3 * d.command_deadline_s, base.position[0], base.position[1], base.position[2], base.orientation.w(),
          base.orientation.x(), base.orientation.y(), base.orientation.z());
    }
    return 0;
  }
  if (*groups) {
    const auto give_up = std::chrono::steady_clock::now() + wait;
    while (client.groups().empty() && std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto described = client.groups();
    if (described.empty()) {
      fmt::print("no device groups on domain {}\n", domain);
      return 1;
    }
    for (const auto& g : described) {
      fmt::print("{:<16} devices: {}; hard minimum {} m, repulsion from {} m; {}\n", g.group,
                 fmt::join(g.devices, ", "), g.min_distance_m, g.repulsion_distance_m,
                 g.own_loop ? "a loop of its own" : "the session's loop");
    }
    return 0;
  }
  if (all) {  // every server answers; the reply shown is the first
    if (*estop) return report(client.emergency_stop_group("*", wait));
    return report(client.recover_group("*", wait));
  }
  if (!group.empty()) {
    if (!client.wait_for_group(group, wait)) {
      fmt::print(stderr, "no device group '{}' on domain {}\n", group, domain);
      return 2;
    }
    if (*estop) return report(client.emergency_stop_group(group, wait));
    if (*recover) return report(client.recover_group(group, wait));
    if (*release) return report(client.release_group(group, wait));
    const int code = report(client.claim_group(group, wait));
    if (code != 0 || hold == 0.0) return code;
    run_for(hold < 0.0 ? 0.0 : hold);
    return report(client.release_group(group, wait));
  }
  if (!client.wait_for_device(device, wait)) {
    fmt::print(stderr, "no device '{}' on domain {}\n", device, domain);
    return 2;
  }
  if (*claim) {
    const int code = report(client.claim(device, wait));
    if (code != 0 || hold == 0.0) return code;
    run_for(hold < 0.0 ? 0.0 : hold);
    return report(client.release(device, wait));
  }
  if (*release) return report(client.release(device, wait));
  if (*switch_cmd) return report(client.switch_scheme(device, scheme, wait));
  if (*set) return report(client.set_parameter(device, parameter, values, wait));
  if (*get) {
    const Client::ParameterAnswer a = client.describe_parameter(device, parameter, wait);
    if (!a.info) return report(a.reply);
    print_parameter(*a.info);
    return 0;
  }
  if (*params) {
    const Client::ParameterList described = client.parameters(device, wait);
    if (!described.reply.accepted) return report(described.reply);
    std::vector<hapticd::ParameterInfo> shown;
    for (const auto& p : described.parameters)
      if ((!tunable_only || p.tunable) && (stage_filter.empty() || p.name.starts_with(stage_filter + ".")))
        shown.push_back(p);
    print_parameter_table(shown);
    return 0;
  }
  if (*estop) return report(client.emergency_stop(device, wait));
  if (*recover) return report(client.recover(device, wait));
  if (*op) return report(client.operator_command(device, what, values, wait));

  if (*watch) {
    std::mutex m;
    auto last = std::chrono::steady_clock::now() - std::chrono::hours(1);
    const auto period = std::chrono::duration<double>(1.0 / rate);
    // Every line names its device; flags by name; a fault report from before this watch says so.
    client.on_event([&](const hapticd::client::Event& e) {
      if (e.device != device) return;
      std::lock_guard lock(m);
      print_event(e);
    });
    // A report of a fault before the first state this watch saw (a late joiner gets the newest) is marked so.
    std::atomic<std::uint64_t> first_cycle{0};
    client.on_fault_report([&](const hapticd::client::FaultReport& r) {
      if (r.device != device) return;
      const std::uint64_t first = first_cycle.load();
      std::lock_guard lock(m);
      print_fault_report(r, first == 0 || r.cycle < first);
    });
    client.on_state([&](const hapticd::client::DeviceState& s) {
      if (s.device != device) return;
      std::uint64_t none = 0;
      first_cycle.compare_exchange_strong(none, s.cycle);
      const auto now = std::chrono::steady_clock::now();
      if (now - last < period) return;
      last = now;
      std::lock_guard lock(m);
      print_state(s);
    });
    run_for(duration);
    client.on_state({});
    client.on_event({});
    client.on_fault_report({});
    return 0;
  }
  if (*record) return record_states(client, device, file, duration, wait);
  return 0;
}
}  // namespace

// Every error ends with a message and exit code 2, never an abort: a DDS participant that cannot be made (a
// malformed HAPTICD_DDS_NETWORK, a Cyclone configuration or DDS Security refusing it), a bad client id.
int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapticctl: %s\n", e.what());
    return 2;
  }
}
