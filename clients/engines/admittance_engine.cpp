// hapticd-admittance-engine: an example admittance-type rendering engine. It takes the operator's wrench
// from each device state, integrates its own virtual object - a mass with damping resting against a soft
// floor below the start position - and sends the object's motion as a MOTION command, which the server's
// admittance model follows. The device then displays the engine's object: pushing down meets the floor.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "claim_keeper.hpp"
#include "engine_main.hpp"
#include "hapticd/client/client.hpp"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }
}  // namespace

namespace {
int run(int argc, char** argv) {
  CLI::App app{"hapticd-admittance-engine: a virtual mass on a floor, sent as desired motion"};
  std::string device = "vishard3", id = "admittance-engine";
  int domain = 0;
  double duration = 0.0, mass = 2.0, damping = 20.0, floor_depth = 0.02, floor_stiffness = 3000.0;
  app.add_option("--device", device, "device to claim");
  app.add_option("--id", id, "client id");
  app.add_option("--domain", domain, "DDS domain")->check(CLI::Range(0, 230));
  app.add_option("--duration", duration, "stop after this many seconds (0: until SIGINT/SIGTERM)");
  app.add_option("--mass", mass, "virtual mass [kg]")->check(CLI::PositiveNumber);
  app.add_option("--damping", damping, "virtual damping [N s/m]")->check(CLI::NonNegativeNumber);
  app.add_option("--floor-depth", floor_depth, "floor this far below the start position [m]");
  app.add_option("--floor-stiffness", floor_stiffness, "floor stiffness [N/m]")->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  if (std::getenv("HAPTICD_PARSE_ONLY") != nullptr) {  // the documentation's commands test (docs_commands)
    std::fputs("hapticd-admittance-engine: the command line parsed (HAPTICD_PARSE_ONLY is set: nothing run)\n", stderr);
    return 0;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  hapticd::client::Client client({id, domain});
  const auto first = client.wait_for_state(device, std::chrono::seconds(10));
  if (!first) {
    fmt::print(stderr, "admittance-engine: no device '{}' on domain {}\n", device, domain);
    return 1;
  }
  hapticd::Pose object = first->pose;
  const double floor_z = object.position.z() - floor_depth;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  std::int64_t last_time = first->loop_time_ns;
  std::atomic<std::uint64_t> answered{0};
  const auto claim = client.claim(device);
  if (!claim.accepted) {
    fmt::print(stderr, "admittance-engine: cannot claim '{}': {}\n", device, claim.message);
    return 2;
  }
  client.on_state([&](const hapticd::client::DeviceState& s) {
    if (s.device != device) return;
    const double dt = std::clamp(static_cast<double>(s.loop_time_ns - last_time) * 1e-9, 0.0, 0.01);
    last_time = s.loop_time_ns;
    Eigen::Vector3d force = s.operator_wrench.force - damping * velocity;
    const double below = floor_z - object.position.z();
    if (below > 0.0)
      force.z() += floor_stiffness * below - 2.0 * std::sqrt(floor_stiffness * mass) * std::min(0.0, velocity.z());
    velocity += dt * force / mass;
    object.position += dt * velocity;
    hapticd::Twist twist;
    twist.linear = velocity;
    client.send_motion(device, object, twist, s.serial);
    answered.fetch_add(1);
  });
  fmt::print("admittance-engine: claimed '{}': a {} kg object, floor {} mm below\n", device, mass, 1e3 * floor_depth);
  const auto start = std::chrono::steady_clock::now();
  int code = 0;
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!hapticd::examples::keep_claim(client, device, "admittance-engine")) {
      code = hapticd::examples::kExitClaimLost;
      break;
    }
    if (duration > 0.0 && std::chrono::steady_clock::now() - start > std::chrono::duration<double>(duration)) break;
  }
  client.on_state({});
  (void)client.release(device, std::chrono::milliseconds(500));
  fmt::print("admittance-engine: answered {} states\n", answered.load());
  return code;
}
}  // namespace

int main(int argc, char** argv) {
  return hapticd::examples::guarded_main("hapticd-admittance-engine", run, argc, argv);
}
