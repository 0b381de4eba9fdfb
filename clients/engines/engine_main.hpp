#pragma once
// The shipped engines' start-up, once: the options every engine takes (--device or --group, --id, --domain,
// --duration, --wait), the documentation's parse-only mode, SIGINT and SIGTERM ending the engine's run, and every
// error ending with a message on standard error and exit code 2, never an abort (a DDS participant that cannot be
// made, a bad client id, a scene that does not load). What an engine does around its physics is
// hapticd::client::Engine's.
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <string>

#include "hapticd/client/engine.hpp"

namespace hapticd::examples {

struct EngineCommandLine {
  std::string device, group, id;
  int domain = 0;
  double duration_s = 0.0, wait_s = 10.0;

  // The helper's options for an engine called `name`.
  [[nodiscard]] client::EngineOptions options(std::string name) const {
    client::EngineOptions o;
    o.name = std::move(name);
    o.device = device;
    o.group = group;
    o.wait = client::Timeout(wait_s);
    o.duration = client::Timeout(duration_s);
    return o;
  }
  [[nodiscard]] client::ClientOptions client() const { return {id, domain}; }
};

// Which of --device and --group an engine takes.
enum class Claims { device, group, device_or_group };

inline void add_engine_options(CLI::App& app, EngineCommandLine& c, Claims claims) {
  if (claims != Claims::group) app.add_option("--device", c.device, "the device to claim");
  if (claims != Claims::device) {
    auto* group = app.add_option("--group", c.group, "the group to claim (one answer per group state)");
    if (claims == Claims::device_or_group) group->excludes("--device");
  }
  app.add_option("--id", c.id, "client id (the owner name)");
  app.add_option("--domain", c.domain, "DDS domain")->check(CLI::Range(0, 230));
  app.add_option("--duration", c.duration_s,
                 "stop after this many seconds (0: until SIGINT/SIGTERM or the server ends)");
  app.add_option("--wait", c.wait_s, "how long to wait for the device or group to appear");
}

// Parses the command line and calls `run` (unless HAPTICD_PARSE_ONLY is set: the documentation's commands test,
// docs_commands); its result is the exit code.
inline int engine_main(const char* program, CLI::App& app, int argc, char** argv, const std::function<int()>& run) {
  try {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return app.exit(e);
    }
    if (std::getenv("HAPTICD_PARSE_ONLY") != nullptr) {
      std::fprintf(stderr, "%s: the command line parsed (HAPTICD_PARSE_ONLY is set: nothing run)\n", program);
      return 0;
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    std::signal(SIGINT, [](int) { client::Engine::stop_all(); });
    std::signal(SIGTERM, [](int) { client::Engine::stop_all(); });
    return run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", program, e.what());
    return 2;
  }
}

}  // namespace hapticd::examples
