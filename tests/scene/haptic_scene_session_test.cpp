// The haptic_scene model on the simulated ViSHaRD3 in lockstep (docs/haptic-scene.md): a scene's plane feels as
// the model toolbox's analytic wall of the same stiffness does under the same guided motion; friction on the
// device sticks to the static cone and slides on the dynamic one; admittance display stops the operator's push at
// the scene's wall; a broken scene file is a configuration error naming the file, the line and the key; a cycle
// allocates nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/test_paths.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

const char* const kOpenLoop = "      plugin: impedance\n      parameters: {task: translation, force_gain: 0}\n";

std::string scene_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / ("hapticd-scene-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

// The guide drags the handle along `path` (a ramp from 0.3 s at its rate per second).
std::string guided(const std::string& path, const std::string& model) {
  return test::sim_vishard3_session_head("v3", 5) + R"(        attachment: position_source
        source_path: ramp
        source_path_m: )" +
         path + R"(
        source_path_start_s: 0.3
    virtual_model:
)" + model +
         "    controller:\n" + kOpenLoop;
}

TEST(HapticSceneSession, ASceneWallFeelsAsTheAnalyticWallOfTheSameStiffness) {
  // The wall's surface 1 mm ahead of the handle's start: the scene's plane lies 1 mm + the proxy's radius ahead.
  const std::string scene = scene_file("wall.yaml", R"(objects:
  - {name: wall, shape: plane, position: [0.006, 0, 0], normal: [-1, 0, 0], material: {stiffness: 2000, damping: 0}}
)");
  Session with_scene = test::build_test_session(guided(
      "[0.005, 0, 0]",
      "      plugin: haptic_scene\n      parameters: {scene: " + scene + ", origin: handle, proxy_radius_m: 0.005}\n"));
  Session with_wall = test::build_test_session(guided(
      "[0.005, 0, 0]",
      "      plugin: scripted_wrench\n      parameters: {display: impedance, signal: constant, walls: [0.001, 0, "
      "0, -1, 0, 0], walls_relative: true, wall_stiffness_n_per_m: 2000, wall_damping_n_s_per_m: 0}\n"));
  double largest = 0.0;
  for (int k = 0; k < 3000; ++k) {  // 1.5 s: up to 5 mm deep
    with_scene.step(1);
    with_wall.step(1);
    const DeviceView a = with_scene.device("v3"), b = with_wall.device("v3");
    ASSERT_TRUE(a.fault.empty()) << a.fault;
    const double expected = b.task.wrench.force.x();
    EXPECT_NEAR(a.task.wrench.force.x(), expected, 0.01 * std::abs(expected) + 2e-3) << "cycle " << k;
    EXPECT_NEAR(a.task.wrench.force.y(), 0.0, 1e-9);
    largest = std::max(largest, -a.task.wrench.force.x());
  }
  EXPECT_GT(largest, 2000 * 0.004) << "the guide went about 4.5 mm deep";
}

TEST(HapticSceneSession, FrictionOnTheDeviceSticksThenSlides) {
  // A floor 1 mm under the proxy; the guide presses in and drags along x at once.
  const std::string scene = scene_file("floor.yaml", R"(materials:
  rough: {stiffness: 2000, damping: 0, static_friction: 0.8, dynamic_friction: 0.4}
objects:
  - {name: floor, shape: plane, position: [0, 0, -0.006], material: rough}
)");
  Session s = test::build_test_session(guided(
      "[0.01, 0, -0.004]",
      "      plugin: haptic_scene\n      parameters: {scene: " + scene + ", origin: handle, proxy_radius_m: 0.005}\n"));
  std::vector<double> ratio;
  for (int k = 0; k < 4000; ++k) {
    s.step(1);
    const DeviceView v = s.device("v3");
    ASSERT_TRUE(v.fault.empty()) << v.fault;
    const double normal = v.task.wrench.force.z(),
                 tangential = std::hypot(v.task.wrench.force.x(), v.task.wrench.force.y());
    if (normal > 1.0) ratio.push_back(tangential / normal);
  }
  ASSERT_GT(ratio.size(), 1000u);
  // The arm under the guide does not move perfectly evenly: the proxy sticks again whenever the handle's motion
  // along the floor falters, and breaks free at the static cone - stick-slip between the two cones.
  const double peak = *std::max_element(ratio.begin(), ratio.end());
  EXPECT_LT(peak, 0.8 + 0.02) << "never beyond the static cone";
  EXPECT_GT(peak, 0.75) << "it stuck first, up to the static cone";
  const auto first_slip = std::find_if(ratio.begin() + 1, ratio.end(), [&](double r) { return r < peak - 0.2; });
  ASSERT_NE(first_slip, ratio.end()) << "it never slipped";
  const double lowest = *std::min_element(first_slip, ratio.end());
  EXPECT_NEAR(lowest, 0.4, 0.02) << "sliding, the dynamic cone";
}

TEST(HapticSceneSession, InAdmittanceDisplayTheOperatorsPushStopsAtTheSceneWall) {
  const std::string scene = scene_file("push.yaml", R"(objects:
  - {name: wall, shape: box, size: [0.02, 0.2, 0.2], position: [0.025, 0, 0], material: {stiffness: 3000, damping: 20}}
)");
  const std::string yaml =
      test::sim_vishard3_session_head("v3", 5) + R"(        sensor_accelerations: true
        attachment: operator
        operator_force: step
        operator_force_n: [12, 0, 0]
        operator_force_start_s: 0.2
    virtual_model:
      plugin: haptic_scene
      parameters: {scene: )" +
      scene +
      R"(, display: admittance, origin: handle, mass_kg: [3, 3, 3], damping_n_s_per_m: [30, 30, 30],
                   rotation: false}
    controller:
      plugin: resolved_acceleration
      parameters: {task: translation}
)";
  Session s = test::build_test_session(yaml);
  const double start = [&] {
    s.step(1);
    return s.device("v3").handle_pose.position.x();
  }();
  s.step(8000);  // 4 s
  const DeviceView v = s.device("v3");
  ASSERT_TRUE(v.fault.empty()) << v.fault;
  // The box's face at 15 mm, the proxy's radius 5 mm: contact from 10 mm on. At rest the operator's push on the
  // handle (what is left of the 12 N after the operator's own arm spring) is the wall's: 3000 N/m x the depth.
  const double depth = v.handle_pose.position.x() - start - 0.010;
  EXPECT_GT(depth, 0.001);
  EXPECT_LT(depth, 0.004);
  EXPECT_NEAR(v.operator_wrench.force.x(), 3000.0 * depth, 0.05 * 3000.0 * depth);
  EXPECT_LT(v.handle_twist.linear.norm(), 1e-3) << "at rest";
}

TEST(HapticSceneSession, ABrokenSceneFileIsAConfigErrorNamingTheFileTheLineAndTheKey) {
  const std::string scene =
      scene_file("broken.yaml", "objects:\n  - name: ball\n    shape: sphere\n    radius: -0.02\n");
  const std::string error = test::config_error_of(
      guided("[0.005, 0, 0]", "      plugin: haptic_scene\n      parameters: {scene: " + scene + "}\n"));
  EXPECT_NE(error.find("broken.yaml:4: objects[0].radius: must be positive"), std::string::npos) << error;
  EXPECT_NE(error.find("scene"), std::string::npos) << error;
  const std::string missing = test::config_error_of(
      guided("[0.005, 0, 0]", "      plugin: haptic_scene\n      parameters: {scene: /nonexistent/scene.yaml}\n"));
  EXPECT_NE(missing.find("/nonexistent/scene.yaml"), std::string::npos) << missing;
}

TEST(HapticSceneSession, ACycleAllocatesNothing) {
  const std::string scene = scene_file("many.yaml", R"(materials:
  m: {stiffness: 2000, static_friction: 0.5, dynamic_friction: 0.3, texture_amplitude: 0.0001}
objects:
  - {name: floor, shape: plane, position: [0, 0, -0.006], material: m}
  - {name: ball, shape: sphere, radius: 0.01, position: [0.012, 0, 0], material: m}
  - {name: post, shape: cylinder, radius: 0.004, length: 0.05, position: [0, 0.012, 0], material: m}
  - {name: bar, shape: capsule, radius: 0.004, length: 0.05, position: [0, -0.012, 0], rpy_deg: [90, 0, 0], material: m}
)");
  Session s = test::build_test_session(guided(
      "[0.01, 0, -0.004]", "      plugin: haptic_scene\n      parameters: {scene: " + scene + ", origin: handle}\n"));
  EXPECT_EQ(test::allocations_over_cycles(test::device_of(s), 3000), 0u);
}

}  // namespace
}  // namespace hapticd::server
