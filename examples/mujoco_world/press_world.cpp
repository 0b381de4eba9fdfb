// A MuJoCo world coupled to a hand without any server: the table scene's proxy is pulled towards a hand that moves
// 60 mm along x, through where the fixed box stands (its face 50 mm ahead). The box stops the proxy; the coupling's
// spring stretches and its force is what a device would render. Prints where the proxy stopped and the force.
// Usage: press_world SCENE.xml
#include <algorithm>
#include <cstdio>
#include <vector>

#include "hapticd/mujoco/coupled_world.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: press_world SCENE.xml\n");
    return 2;
  }
  try {
    hapticd::mujoco::WorldOptions options;
    options.scene = argv[1];
    options.devices = {"hand"};
    options.state_period_s = 1e-3;  // a device's state every millisecond
    hapticd::mujoco::CoupledWorld world(options);
    world.set_gains(0, hapticd::mujoco::CouplingGains{3000.0, 30.0, 0.0, 0.0});
    std::vector<hapticd::mujoco::Hand> hands(1);
    world.place(0, hands[0]);
    for (int k = 0; k < 2000; ++k) {  // 2 s: the hand moves 60 mm along x in the first second, then holds
      hands[0].pose.position.x() = 0.06 * std::min(1.0, k / 1000.0);
      if (!world.step(hands).stable) {
        std::fprintf(stderr, "press_world: the world went unstable\n");
        return 1;
      }
    }
    const hapticd::mujoco::Proxy p = world.proxy(0);
    std::printf("proxy at x = %.2f mm, hand at %.2f mm; the coupling pulls with %.2f N, the box pushes back %.2f N\n",
                1e3 * p.pose.position.x(), 1e3 * hands[0].pose.position.x(), p.coupling_force.x(),
                -p.contact_force.x());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "press_world: %s\n", e.what());
    return 2;
  }
}
