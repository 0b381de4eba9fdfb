// hapticd-scene-engine: an example impedance-type rendering engine. It renders a scene of a wall, a box and a
// sphere through the server's virtual coupling: for every device state it computes the proxy (the handle
// kept on the objects' surfaces) and sends it as a COUPLING command; the server's coupling spring turns the
// difference into force. It prints contacts as they happen and can write a CSV of position, proxy and force.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <thread>

#include "claim_keeper.hpp"
#include "engine_main.hpp"
#include "hapticd/client/client.hpp"
#include "scene.hpp"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }
}  // namespace

namespace {
int run(int argc, char** argv) {
  CLI::App app{"hapticd-scene-engine: renders a wall, a box and a sphere through the virtual coupling"};
  std::string device = "vishard3", id = "scene-engine", csv;
  int domain = 0;
  double duration = 0.0, wait = 10.0;
  app.add_option("--device", device, "device to claim");
  app.add_option("--id", id, "client id (the owner name)");
  app.add_option("--domain", domain, "DDS domain")->check(CLI::Range(0, 230));
  app.add_option("--duration", duration, "stop after this many seconds (0: until SIGINT/SIGTERM or the server ends)");
  app.add_option("--wait", wait, "how long to wait for the device to appear");
  app.add_option("--csv", csv, "write time, handle position, proxy, rendered force and operator force here");
  CLI11_PARSE(app, argc, argv);
  if (std::getenv("HAPTICD_PARSE_ONLY") != nullptr) {  // the documentation's commands test (docs_commands)
    std::fputs("hapticd-scene-engine: the command line parsed (HAPTICD_PARSE_ONLY is set: nothing run)\n", stderr);
    return 0;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  hapticd::client::Client client({id, domain});
  const auto description = client.wait_for_device(device, std::chrono::duration<double>(wait));
  if (!description) {
    fmt::print(stderr, "scene-engine: no device '{}' on domain {} within {} s\n", device, domain, wait);
    return 1;
  }
  const auto first = client.wait_for_state(device, std::chrono::duration<double>(wait));
  if (!first) {
    fmt::print(stderr, "scene-engine: no state from '{}'\n", device);
    return 1;
  }
  // The scene sits at the device's start pose (the description is re-sent with it once the loop runs), so an
  // engine that reconnects finds its objects where they were.
  const auto described = client.wait_for_device(device, std::chrono::duration<double>(wait), true);
  if (!described) {
    fmt::print(stderr, "scene-engine: '{}' has not started\n", device);
    return 1;
  }
  const Eigen::Vector3d origin = described->start_pose->position;
  const hapticd::examples::Scene scene = hapticd::examples::demo_scene();

  std::ofstream out;
  if (!csv.empty()) {
    out.open(csv);
    out << "time_s,x,y,z,proxy_x,proxy_y,proxy_z,env_fx,env_fy,env_fz,op_fx,op_fy,op_fz,contact\n";
  }
  std::mutex out_mutex;
  std::string last_contact;
  double deepest = 0.0;
  std::atomic<std::uint64_t> answered{0};
  std::atomic<bool> server_gone{false};
  const auto claim = client.claim(device);
  if (!claim.accepted) {
    fmt::print(stderr, "scene-engine: cannot claim '{}': {}\n", device, claim.message);
    return 2;
  }
  client.on_state([&](const hapticd::client::DeviceState& s) {
    if (s.device != device) return;
    // The coupling pulls the server's virtual body (the target pose); its proxy is the body kept out of the
    // objects (using the measured handle instead would tie the body to the handle in free space).
    const Eigen::Vector3d x = s.target_pose.position - origin;
    const Eigen::Vector3d p = scene.proxy(x);
    hapticd::Pose proxy = s.pose;
    proxy.position = origin + p;
    hapticd::Twist twist;  // slides with the handle along a surface, never into it
    twist.linear = scene.proxy_velocity(x, p, s.twist.linear);
    client.send_coupling(device, proxy, twist, s.serial);
    answered.fetch_add(1);
    // The session ends: its torques ramp down while the states still come - answered to the last (an engine that
    // fell silent here would make the server count missed deadlines).
    if (s.mode == hapticd::client::Mode::stopping || s.mode == hapticd::client::Mode::off) server_gone.store(true);
    const std::string contact = scene.contact(x);
    const double depth = (p - x).norm();
    std::lock_guard lock(out_mutex);
    if (contact != last_contact) {
      fmt::print("t={:6.3f} s  {}  handle at ({:+.1f}, {:+.1f}, {:+.1f}) mm, operator force {:.1f} N\n",
                 static_cast<double>(s.loop_time_ns) * 1e-9,
                 contact.empty() ? "free space  " : fmt::format("touches the {}", contact), 1e3 * x.x(), 1e3 * x.y(),
                 1e3 * x.z(), s.operator_wrench.force.norm());
      last_contact = contact;
    }
    deepest = std::max(deepest, depth);
    if (out.is_open()) {
      out << fmt::format(
          "{:.4f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{}\n", s.time_s(),
          x.x(), x.y(), x.z(), p.x(), p.y(), p.z(), s.environment_wrench.force.x(), s.environment_wrench.force.y(),
          s.environment_wrench.force.z(), s.operator_wrench.force.x(), s.operator_wrench.force.y(),
          s.operator_wrench.force.z(), contact);
    }
  });
  fmt::print(
      "scene-engine: claimed '{}'; rendering a wall at x = +30 mm, a cube below it (top at y = -35 mm) and a "
      "sphere at (-30, -35) mm, r = 25 mm\n",
      device);
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t last_answered = 0;
  auto last_progress = start;
  int code = 0;
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!hapticd::examples::keep_claim(client, device, "scene-engine")) {
      code = hapticd::examples::kExitClaimLost;
      break;
    }
    const auto now = std::chrono::steady_clock::now();
    if (duration > 0.0 && now - start > std::chrono::duration<double>(duration)) break;
    if (answered.load() != last_answered) {
      last_answered = answered.load();
      last_progress = now;
    } else if (server_gone.load() && now - last_progress > std::chrono::milliseconds(200)) {
      break;  // the session ended: no state since its last stopping one
    } else if (now - last_progress > std::chrono::seconds(3)) {
      fmt::print("scene-engine: no state for 3 s, the server is gone\n");
      break;
    }
  }
  client.on_state({});
  (void)client.release(device, std::chrono::milliseconds(500));
  std::lock_guard lock(out_mutex);
  fmt::print("scene-engine: answered {} states; deepest penetration {:.2f} mm\n", answered.load(), 1e3 * deepest);
  return code;
}
}  // namespace

int main(int argc, char** argv) { return hapticd::examples::guarded_main("hapticd-scene-engine", run, argc, argv); }
