// hapticd-bimanual-engine: an example engine for a device group (docs/multi-device.md, "Bimanual coupling"). It
// claims a two-hand group and renders one virtual box held by both hands, resting on a table under them, through
// the devices' virtual coupling with one group command per cycle; the operators lift and turn it. It prints the
// box's height, turn and internal force now and then.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "bimanual.hpp"
#include "claim_keeper.hpp"
#include "engine_main.hpp"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }
}  // namespace

namespace {
int run(int argc, char** argv) {
  CLI::App app{"hapticd-bimanual-engine: a virtual box held by the two hands of a device group"};
  std::string group = "hands", id = "bimanual-engine";
  int domain = 0;
  double duration = 0.0, wait = 10.0, mass = 1.0;
  std::vector<double> size = {0.32, 0.15, 0.10};
  app.add_option("--group", group, "the group to claim (two devices with a virtual coupling)");
  app.add_option("--id", id, "client id (the owner name)");
  app.add_option("--domain", domain, "DDS domain")->check(CLI::Range(0, 230));
  app.add_option("--mass", mass, "the box's mass [kg]")->check(CLI::Range(0.01, 50.0));
  app.add_option("--size", size, "the box's edges [m]: along the line between the hands, across, up")->expected(3);
  app.add_option("--duration", duration, "stop after this many seconds (0: until SIGINT/SIGTERM)");
  app.add_option("--wait", wait, "how long to wait for the group to appear");
  CLI11_PARSE(app, argc, argv);
  if (std::getenv("HAPTICD_PARSE_ONLY") != nullptr) {  // the documentation's commands test (docs_commands)
    std::fputs("hapticd-bimanual-engine: the command line parsed (HAPTICD_PARSE_ONLY is set: nothing run)\n", stderr);
    return 0;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  hapticd::client::Client client({id, domain});
  hapticd::model::SharedBodySettings box;
  box.mass_kg = mass;
  box.size_m = Eigen::Vector3d(size[0], size[1], size[2]);
  hapticd::examples::BimanualEngine engine(client, group, box);
  if (const std::string error = engine.connect(std::chrono::duration<double>(wait)); !error.empty()) {
    fmt::print(stderr, "bimanual-engine: {}\n", error);
    return 1;
  }
  const auto start = engine.start();
  fmt::print("bimanual-engine: claimed '{}'; a {} kg box between the hands at z = {:+.3f} m, on a table\n", group, mass,
             start.position.z());
  const auto began = std::chrono::steady_clock::now();
  std::uint64_t seen = 0;
  int code = 0;
  const auto described = client.wait_for_group(group, std::chrono::seconds(1));
  const std::vector<std::string> hands = described ? described->devices : std::vector<std::string>{};
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    if (!hands.empty() && !hapticd::examples::keep_claim(client, group, "bimanual-engine", true, hands.front())) {
      code = hapticd::examples::kExitClaimLost;
      break;
    }
    const auto r = engine.report();
    if (r.answered == seen) {
      if (seen > 0) break;  // the server has ended
      continue;
    }
    seen = r.answered;
    fmt::print("box {:+6.1f} mm above its start, turned {:+5.1f} deg, internal force {:+6.2f} N, table {:5.2f} N\n",
               1e3 * (r.position.z() - start.position.z()), r.yaw_deg - start.yaw_deg, r.internal_force_n,
               r.table_force_n);
    if (duration > 0.0 && std::chrono::steady_clock::now() - began > std::chrono::duration<double>(duration)) break;
  }
  fmt::print("bimanual-engine: answered {} group states\n", engine.report().answered);
  (void)client.release_group(group, std::chrono::seconds(2));
  return code;
}
}  // namespace

int main(int argc, char** argv) { return hapticd::examples::guarded_main("hapticd-bimanual-engine", run, argc, argv); }
