// hapticd: the real-time haptic control server.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>

#include "app/commands.hpp"
#include "config/config_error.hpp"
#include "hapticd/api_version.hpp"
#include "hapticd/recording/recording_file.hpp"

namespace {

int run_command(int argc, char** argv) {
  using namespace hapticd::server;
  CLI::App app{"hapticd - real-time haptic control server"};
  app.set_version_flag("--version",
                       std::string("hapticd 0.1.0 (plugin API ") + std::to_string(hapticd::kApiVersion) + ")");

  RunOptions run;
  std::string check_file;
  std::string describe_name;
  bool list = false;
  bool describe_server = false;
  std::string log_level = "info";
  double duration = -1.0;
  std::string clock;

  auto* config_opt = app.add_option("--config", run.config_file, "run the session described by this YAML file");
  auto* check_opt = app.add_option("--check-config", check_file,
                                   "validate a session file (loads and configures its plugins) and exit");
  auto* list_opt = app.add_flag("--list-plugins", list,
                                "list the plugins on the search paths (with --config: also its plugin_paths)");
  auto* describe_opt =
      app.add_option("--describe-plugin", describe_name, "print a plugin's parameters (type, unit, bounds, default)");
  auto* server_opt = app.add_flag("--describe-config", describe_server,
                                  "print the settings of a session file's server, dds and live_view sections");
  auto* duration_opt = app.add_option("--duration", duration, "run for this many seconds (overrides server.duration_s)")
                           ->check(CLI::NonNegativeNumber);
  auto* clock_opt = app.add_option("--clock", clock, "realtime, lockstep or device (overrides server.clock)")
                        ->check(CLI::IsMember({"realtime", "lockstep", "device"}));
  app.add_option("--set", run.sets,
                 "override a key of the session file before it is validated, e.g. --set server.seed=7 --set "
                 "devices.v3.virtual_model.parameters.mass_kg=[2,2,2] (a device entry by its name; the value is YAML)");
  app.add_option("--stats-json", run.stats_json, "write loop statistics (histograms, percentiles) to this JSON file");
  app.add_option(
         "--record", run.record_file,
         "record every cycle of every device to this HDF5 file, .h5 (docs/recording.md; hapticctl export FILE --csv)")
      ->check(CLI::Validator([](const std::string& f) { return hapticd::recording::recording_name_problem(f); },
                             "FILE.h5"));
  int live_view_port = 0;
  auto* live_view_opt =
      app.add_option("--live-view", live_view_port,
                     "serve the live view (Foxglove WebSocket, docs/live-view.md) on this port of 127.0.0.1 unless "
                     "the session file's live_view section names another address; 0 takes any free port")
          ->check(CLI::Range(0, 65535));
  int dds_domain = 0;
  auto* dds_opt = app.add_option("--dds-domain", dds_domain,
                                 "run the DDS interface on this domain (loopback-only "
                                 "configuration unless dds.cyclone_config says otherwise)")
                      ->check(CLI::Range(0, 230));
  app.add_flag("--busy-machine", run.busy_machine,
               "a development machine that is busy with other work: the loop watchdogs of simulated devices (sim, "
               "playback) loosened to a 1 s stall and 2000 overruns; other devices keep theirs (docs/running.md)");
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));
  check_opt->excludes(config_opt);
  server_opt->excludes(check_opt)->excludes(list_opt)->excludes(describe_opt);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version: 0; any other command-line error is a configuration error, exit 2, said by CLI11.
    return app.exit(e) == 0 ? kExitOk : kExitConfigError;
  }
  if (std::getenv("HAPTICD_PARSE_ONLY") != nullptr) {  // the documentation's commands test (docs_commands)
    std::fputs("hapticd: the command line parsed (HAPTICD_PARSE_ONLY is set: nothing run)\n", stderr);
    return 0;
  }

  spdlog::set_level(spdlog::level::from_str(log_level));
  spdlog::set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");

  if (*duration_opt) run.duration_s = duration;
  if (*clock_opt) run.clock = clock;
  if (*dds_opt) run.dds_domain = dds_domain;
  if (*live_view_opt)  // before the --set overrides: an explicit --set live_view.port wins
    run.sets.insert(run.sets.begin(), {"live_view.enabled=true", "live_view.port=" + std::to_string(live_view_port)});

  if (describe_server) return describe_config(run.config_file);
  if (!describe_name.empty()) return describe_plugin(describe_name, run.config_file);
  if (list) return list_plugins(run.config_file);
  if (!check_file.empty()) return check_config(check_file, run.sets);
  if (!run.config_file.empty()) return run_session(run);
  std::fputs(app.help().c_str(), stdout);
  return 1;
}

}  // namespace

// Every error ends with a message and an exit code: nothing escapes as an abort. Devices are powered only
// once every resource of the session is in place (commands.cpp, Executor::run), so an error here leaves them off.
int main(int argc, char** argv) {
  using namespace hapticd::server;
  try {
    return run_command(argc, argv);
  } catch (const ConfigError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitConfigError;
  } catch (const std::bad_alloc&) {
    std::fputs("error: out of memory (raise the process's memory limit)\n", stderr);
    return kExitRuntimeError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitRuntimeError;
  } catch (...) {
    std::fputs("error: an unknown error ended hapticd\n", stderr);
    return kExitRuntimeError;
  }
}
