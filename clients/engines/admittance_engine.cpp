// hapticd-admittance-engine: an example admittance-type rendering engine. It takes the operator's wrench
// from each device state, integrates its own virtual object - a mass with damping resting against a soft
// floor below the start position - and sends the object's motion as a MOTION command, which the server's
// admittance model follows. The device then displays the engine's object: pushing down meets the floor.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "engine_main.hpp"

namespace {

using hapticd::client::DeviceState;
using hapticd::client::EngineCommand;

// The engine's object: a mass with damping against a floor.
struct FloorObject {
  double mass = 2.0, damping = 20.0, floor_depth = 0.02, floor_stiffness = 3000.0;
  hapticd::Pose pose;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  double floor_z = 0.0;
  std::int64_t last_time_ns = 0;

  void place(const DeviceState& s) {
    pose = s.pose;
    floor_z = pose.position.z() - floor_depth;
    velocity.setZero();
    last_time_ns = s.loop_time_ns;
  }
  // One step under the operator's force to the state's time.
  EngineCommand answer(const DeviceState& s) {
    const double dt = std::clamp(static_cast<double>(s.loop_time_ns - last_time_ns) * 1e-9, 0.0, 0.01);
    last_time_ns = s.loop_time_ns;
    Eigen::Vector3d force = s.operator_wrench.force - damping * velocity;
    const double below = floor_z - pose.position.z();
    if (below > 0.0)
      force.z() += floor_stiffness * below - 2.0 * std::sqrt(floor_stiffness * mass) * std::min(0.0, velocity.z());
    velocity += dt * force / mass;
    pose.position += dt * velocity;
    hapticd::Twist twist;
    twist.linear = velocity;
    return EngineCommand::motion(pose, twist, s.serial);
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hapticd-admittance-engine: a virtual mass on a floor, sent as desired motion"};
  hapticd::examples::EngineCommandLine command_line{.device = "vishard3", .id = "admittance-engine"};
  hapticd::examples::add_engine_options(app, command_line, hapticd::examples::Claims::device);
  FloorObject object;
  app.add_option("--mass", object.mass, "virtual mass [kg]")->check(CLI::PositiveNumber);
  app.add_option("--damping", object.damping, "virtual damping [N s/m]")->check(CLI::NonNegativeNumber);
  app.add_option("--floor-depth", object.floor_depth, "floor this far below the start position [m]");
  app.add_option("--floor-stiffness", object.floor_stiffness, "floor stiffness [N/m]")->check(CLI::NonNegativeNumber);
  return hapticd::examples::engine_main("hapticd-admittance-engine", app, argc, argv, [&] {
    hapticd::client::Client client(command_line.client());
    hapticd::client::Engine engine(client, command_line.options("admittance-engine"));
    engine.on_claim([&](bool again) {
      const auto s = client.wait_for_state(engine.target(), std::chrono::seconds(2));
      if (!s) {
        engine.say("no state from '" + engine.target() + "'", true);
        return false;
      }
      object.place(*s);
      if (!again)
        engine.say(fmt::format("claimed '{}': a {} kg object, floor {} mm below", engine.target(), object.mass,
                               1e3 * object.floor_depth));
      return true;
    });
    const auto end = engine.run([&](std::span<const DeviceState* const> s, std::span<EngineCommand> out) {
      out[0] = object.answer(*s[0]);
      return true;
    });
    engine.say(fmt::format("answered {} states", engine.answered()));
    return end.exit_code();
  });
}
