// hapticd-bimanual-engine: an example engine for a device group (docs/multi-device.md, "Bimanual coupling"). It
// claims a two-hand group and renders one virtual box held by both hands, resting on a table under them, through
// the devices' virtual coupling with one group command per cycle; the operators lift and turn it. It prints the
// box's height, turn and internal force now and then.
#include <fmt/format.h>

#include "bimanual.hpp"
#include "engine_main.hpp"

int main(int argc, char** argv) {
  CLI::App app{"hapticd-bimanual-engine: a virtual box held by the two hands of a device group"};
  hapticd::examples::EngineCommandLine command_line{.group = "hands", .id = "bimanual-engine"};
  hapticd::examples::add_engine_options(app, command_line, hapticd::examples::Claims::group);
  hapticd::model::SharedBodySettings box;
  std::vector<double> size = {0.32, 0.15, 0.10};
  app.add_option("--mass", box.mass_kg, "the box's mass [kg]")->check(CLI::Range(0.01, 50.0));
  app.add_option("--size", size, "the box's edges [m]: along the line between the hands, across, up")->expected(3);
  return hapticd::examples::engine_main("hapticd-bimanual-engine", app, argc, argv, [&] {
    box.size_m = Eigen::Vector3d(size[0], size[1], size[2]);
    hapticd::client::Client client(command_line.client());
    hapticd::client::Engine engine(client, command_line.options("bimanual-engine"));
    hapticd::examples::BimanualEngine hands(client, box);
    if (!engine.connect()) return 1;
    if (const std::string e =
            hands.prepare(engine.target(), engine.devices(), hapticd::client::Timeout(command_line.wait_s));
        !e.empty()) {
      engine.say(e, true);
      return 1;
    }
    const hapticd::examples::BoxReport start = hands.start();
    engine.on_claim([&](bool again) {
      if (!again)
        engine.say(fmt::format("claimed '{}'; a {} kg box between the hands at z = {:+.3f} m, on a table",
                               engine.target(), box.mass_kg, start.position.z()));
      return true;
    });
    auto last_print = std::chrono::steady_clock::now();
    engine.on_chores([&] {
      if (std::chrono::steady_clock::now() - last_print < std::chrono::milliseconds(500)) return true;
      last_print = std::chrono::steady_clock::now();
      if (const auto r = hands.report(); r.answered > 0)
        fmt::print("box {:+6.1f} mm above its start, turned {:+5.1f} deg, internal force {:+6.2f} N, table {:5.2f} N\n",
                   1e3 * (r.position.z() - start.position.z()), r.yaw_deg - start.yaw_deg, r.internal_force_n,
                   r.table_force_n);
      return true;
    });
    const auto end = engine.run([&](auto states, auto commands) { return hands.answer(states, commands); });
    engine.say(fmt::format("answered {} group states", hands.report().answered));
    return end.exit_code();
  });
}
