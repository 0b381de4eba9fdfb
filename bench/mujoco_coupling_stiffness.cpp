// The largest virtual-coupling stiffness that stays stable, per shipped MuJoCo scene and its device
// (docs/engines.md, "Physics engines"; docs/measurements.md). Each scene's session runs in lockstep with its world
// (tests/support/coupled_scene.hpp: the engine's round trip of one cycle) while the simulated operator holds the hand
// pressed into one of the scene's fixed objects; the coupling stiffness is raised step by step, its damping with the
// square root of the stiffness (the coupling's damping ratio as the session has it). A stiffness is stable when the
// run ends with no fault, MuJoCo never reset the world, the world accepted the gains (the physics step resolves
// them at the proxy's mass) and the pressed hand is still: its largest velocity over the last 0.25 s below 2 mm/s.
// Usage: mujoco_coupling_stiffness [SCENE...]   (no argument: every scene)
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/coupled_scene.hpp"

namespace {

using hapticd::test::CoupledScene;

struct Case {
  std::string scene;
  std::vector<std::string> devices;
  double stiffness0, damping0;  // the session's
  std::function<void(CoupledScene&)> press;
};

// Brings the hand into the object and presses it there (2 s at 1 kHz).
void drive(CoupledScene& c, const std::string& d, const std::string& what, std::vector<double> v) {
  c.drive(d, what, v);
}

std::vector<Case> cases() {
  return {
      {"table-blocks",
       {"vishard3"},
       3000,
       30,
       [](CoupledScene& c) {
         drive(c, "vishard3", "move", {0.035, 0.0, 0.0, 0.5});
         c.step(700);
         drive(c, "vishard3", "push", {15.0, 0.0, 0.0, 0.3});
       }},
      {"peg-in-hole",
       {"vishard3"},
       3000,
       30,
       [](CoupledScene& c) {
         drive(c, "vishard3", "move", {0.0, 0.0, -0.01, 0.3});  // the peg's tip onto the plate's top
         c.step(500);
         drive(c, "vishard3", "push", {0.0, 0.0, -10.0, 0.3});
       }},
      {"door-drawer",
       {"vishard3"},
       3000,
       30,
       [](CoupledScene& c) {
         drive(c, "vishard3", "move", {-0.08, 0.0, -0.02, 0.8});  // the drawer in, to its stop
         c.step(1000);
         drive(c, "vishard3", "push", {-10.0, 0.0, 0.0, 0.3});
       }},
      {"vishard10-workspace",
       {"vishard10"},
       2000,
       30,
       [](CoupledScene& c) {
         drive(c, "vishard10", "move", {0.0, 0.0, -0.05, 0.5});
         c.step(1400);
         drive(c, "vishard10", "push", {0.0, 0.0, -10.0, 0.3});
       }},
      {"bimanual-box",
       {"left", "right"},
       2000,
       20,
       [](CoupledScene& c) {
         drive(c, "left", "push", {12.0, 0.0, 0.0, 0.3});
         drive(c, "right", "push", {-12.0, 0.0, 0.0, 0.3});
       }},
  };
}

// "" when stable, else why not.
std::string try_stiffness(const Case& k, double stiffness) {
  const double damping = k.damping0 * std::sqrt(stiffness / k.stiffness0);
  std::vector<std::string> overrides;
  for (const std::string& d : k.devices) {
    overrides.push_back("devices." + d +
                        ".virtual_model.parameters.coupling_stiffness_n_per_m=" + std::to_string(stiffness));
    overrides.push_back("devices." + d +
                        ".virtual_model.parameters.coupling_damping_n_s_per_m=" + std::to_string(damping));
  }
  try {
    CoupledScene c(k.scene, overrides);
    const double rate = 1.0 / c.session().period_s();
    c.step(static_cast<std::uint64_t>(0.2 * rate));
    k.press(c);
    c.step(static_cast<std::uint64_t>(1.5 * rate));
    double fastest = 0.0;
    for (std::uint64_t n = 0; n < static_cast<std::uint64_t>(0.25 * rate); ++n) {
      c.step(1);
      for (std::size_t i = 0; i < k.devices.size(); ++i)
        fastest = std::max(fastest, c.view(i).handle_twist.linear.norm());
    }
    for (std::size_t i = 0; i < k.devices.size(); ++i) {
      if (!c.view(i).fault.empty()) return "fault: " + c.view(i).fault;
    }
    if (c.unstable_steps() > 0) return "MuJoCo reset the world";
    if (fastest > 0.002) {
      char why[80];
      std::snprintf(why, sizeof why, "the pressed hand oscillates (%.0f mm/s)", 1e3 * fastest);
      return why;
    }
    return "";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    return what.find("too light") != std::string::npos ? "the proxy is too light for it at the physics step" : what;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<double> stiffnesses = {1000, 2000, 3000, 5000, 8000, 12000, 20000, 30000, 50000};
  std::printf(
      "| scene | device | session's coupling [N/m] | largest stable [N/m] | the next step up "
      "|\n|---|---|---|---|---|\n");
  for (const Case& k : cases()) {
    bool wanted = argc < 2;
    for (int a = 1; a < argc; ++a) wanted = wanted || k.scene == argv[a];
    if (!wanted) continue;
    double largest = 0.0;
    std::string next = "stable to the end of the sweep";
    for (double s : stiffnesses) {
      const std::string why = try_stiffness(k, s);
      std::fprintf(stderr, "%s at %.0f N/m: %s\n", k.scene.c_str(), s, why.empty() ? "stable" : why.c_str());
      if (!why.empty()) {
        char text[200];
        std::snprintf(text, sizeof text, "%.0f N/m: %s", s, why.c_str());
        next = text;
        break;
      }
      largest = s;
    }
    std::string devices;
    for (const std::string& d : k.devices) devices += (devices.empty() ? "" : ", ") + d;
    std::printf("| %s | %s | %.0f | %.0f | %s |\n", k.scene.c_str(), devices.c_str(), k.stiffness0, largest,
                next.c_str());
  }
  return 0;
}
