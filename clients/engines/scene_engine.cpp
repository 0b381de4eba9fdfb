// hapticd-scene-engine: an example impedance-type rendering engine. It renders a scene of a wall, a box and a
// sphere through the server's virtual coupling: for every device state it computes the proxy (the handle
// kept on the objects' surfaces) and sends it as a COUPLING command; the server's coupling spring turns the
// difference into force. It prints contacts as they happen and can write a CSV of position, proxy and force.
#include <fmt/format.h>

#include <fstream>
#include <mutex>

#include "engine_main.hpp"
#include "scene.hpp"

namespace {

using hapticd::client::DeviceState;
using hapticd::client::EngineCommand;

// What the engine renders and reports: the demo scene placed at the device's start pose (so an engine that
// reconnects finds its objects where they were), its contacts as they change, a CSV of every state.
class SceneRenderer {
 public:
  SceneRenderer(const Eigen::Vector3d& origin, const std::string& csv) : origin_(origin) {
    if (csv.empty()) return;
    out_.open(csv);
    if (!out_) throw std::runtime_error("cannot write " + csv);
    out_ << "time_s,x,y,z,proxy_x,proxy_y,proxy_z,env_fx,env_fy,env_fz,op_fx,op_fy,op_fz,contact\n";
  }

  EngineCommand answer(const DeviceState& s) {
    // The coupling pulls the server's virtual body (the target pose); its proxy is the body kept out of the
    // objects (using the measured handle instead would tie the body to the handle in free space).
    const Eigen::Vector3d x = s.target_pose.position - origin_;
    const Eigen::Vector3d p = scene_.proxy(x);
    hapticd::Pose proxy = s.pose;
    proxy.position = origin_ + p;
    hapticd::Twist twist;  // slides with the handle along a surface, never into it
    twist.linear = scene_.proxy_velocity(x, p, s.twist.linear);
    report(s, x, p);
    return EngineCommand::coupling(proxy, twist, s.serial);
  }

  [[nodiscard]] double deepest() const {
    std::lock_guard lock(mutex_);
    return deepest_;
  }

 private:
  void report(const DeviceState& s, const Eigen::Vector3d& x, const Eigen::Vector3d& p) {
    const std::string contact = scene_.contact(x);
    std::lock_guard lock(mutex_);
    if (contact != last_contact_) {
      fmt::print("t={:6.3f} s  {}  handle at ({:+.1f}, {:+.1f}, {:+.1f}) mm, operator force {:.1f} N\n",
                 static_cast<double>(s.loop_time_ns) * 1e-9,
                 contact.empty() ? "free space  " : fmt::format("touches the {}", contact), 1e3 * x.x(), 1e3 * x.y(),
                 1e3 * x.z(), s.operator_wrench.force.norm());
      last_contact_ = contact;
    }
    deepest_ = std::max(deepest_, (p - x).norm());
    if (!out_.is_open()) return;
    const Eigen::Vector3d& fe = s.environment_wrench.force;
    const Eigen::Vector3d& fo = s.operator_wrench.force;
    out_ << fmt::format(
        "{:.4f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{}\n", s.time_s(),
        x.x(), x.y(), x.z(), p.x(), p.y(), p.z(), fe.x(), fe.y(), fe.z(), fo.x(), fo.y(), fo.z(), contact);
  }

  const Eigen::Vector3d origin_;
  const hapticd::examples::Scene scene_ = hapticd::examples::demo_scene();
  mutable std::mutex mutex_;  // the receive thread reports, the main thread reads the deepest
  std::ofstream out_;
  std::string last_contact_;
  double deepest_ = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hapticd-scene-engine: renders a wall, a box and a sphere through the virtual coupling"};
  hapticd::examples::EngineCommandLine command_line{.device = "vishard3", .id = "scene-engine"};
  hapticd::examples::add_engine_options(app, command_line, hapticd::examples::Claims::device);
  std::string csv;
  app.add_option("--csv", csv, "write time, handle position, proxy, rendered force and operator force here");
  return hapticd::examples::engine_main("hapticd-scene-engine", app, argc, argv, [&] {
    hapticd::client::Client client(command_line.client());
    hapticd::client::Engine engine(client, command_line.options("scene-engine"));
    if (!engine.connect()) return 1;
    SceneRenderer scene(engine.description(0).start_pose->position, csv);
    engine.on_claim([&](bool again) {
      if (!again)
        engine.say(fmt::format(
            "claimed '{}'; rendering a wall at x = +30 mm, a cube below it (top at y = -35 mm) and a sphere at "
            "(-30, -35) mm, r = 25 mm",
            engine.target()));
      return true;
    });
    const auto end = engine.run([&](std::span<const DeviceState* const> s, std::span<EngineCommand> out) {
      out[0] = scene.answer(*s[0]);
      return true;
    });
    engine.say(
        fmt::format("answered {} states; deepest penetration {:.2f} mm", engine.answered(), 1e3 * scene.deepest()));
    return end.exit_code();
  });
}
