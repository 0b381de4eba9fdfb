// The haptic_scene model on the simulated ViSHaRD3 in lockstep (docs/haptic-scene.md): a scene's plane feels as
// the model toolbox's analytic wall of the same stiffness does under the same guided motion; friction on the
// device sticks to the static cone and slides on the dynamic one; admittance display stops the operator's push at
// the scene's wall; a broken scene file is a configuration error naming the file, the line and the key; a cycle
// allocates nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "hapticd/json_reader.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "live_view/haptic_scene_view.hpp"
#include "session/device_session.hpp"
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

// The session's scene (its `scene` section): two devices whose haptic_scene models name no file share it; a wall an
// engine adds while they run is felt by both from their next cycle, as the analytic wall of the same stiffness is,
// and no longer once removed; the cycles allocate nothing across the edits.
std::string two_devices_on_the_session_scene(const std::string& scene_section) {
  const std::string model = "      plugin: haptic_scene\n      parameters: {origin: handle, proxy_radius_m: 0.005}\n";
  std::string first = guided("[0.005, 0, 0]", model);
  std::string second = guided("[0.005, 0, 0]", model);
  second = second.substr(second.find("devices:\n") + 9);  // its device entry
  second.replace(second.find("name: v3"), 8, "name: w3");
  first.replace(first.find("devices:\n"), 9, scene_section + "devices:\n");
  return first + second;
}

// 1 mm + the proxy's radius ahead of each handle (the models' origin: the handle), as an engine writes it.
constexpr const char* kWallAhead =
    R"({"name": "wall", "shape": "plane", "position": [0.006, 0, 0], "normal": [-1, 0, 0],
        "material": {"stiffness": 2000, "damping": 0}})";

SceneService& scene_of(Session& s, std::size_t device) { return *test::device_of(s, device).chain().scene->object; }

TEST(HapticSceneSession, TwoDevicesShareTheSessionsSceneAndFeelAWallAddedWhileTheyRun) {
  Session s = test::build_test_session(two_devices_on_the_session_scene("scene:\n"));
  ASSERT_NE(test::device_of(s, 0).chain().scene, nullptr);
  SceneService* shared = &scene_of(s, 0);
  EXPECT_EQ(shared, &scene_of(s, 1));
  s.step(600);  // 0.3 s: the guides have not moved yet
  for (const char* d : {"v3", "w3"}) EXPECT_EQ(s.device(d).task.wrench.force.norm(), 0.0);
  shared->add(kWallAhead);
  s.step(2400);  // 1.2 s more: 5 mm into the wall
  for (const char* d : {"v3", "w3"}) {
    const DeviceView v = s.device(d);
    ASSERT_TRUE(v.fault.empty()) << d << ": " << v.fault;
    EXPECT_LT(v.task.wrench.force.x(), -2000 * 0.004) << d;
    EXPECT_NEAR(v.task.wrench.force.y(), 0.0, 1e-9) << d;
  }
  EXPECT_NEAR(s.device("v3").task.wrench.force.x(), s.device("w3").task.wrench.force.x(), 0.2);
  // Two-way: each hand pushes the wall with the force it feels, reversed, at the point it touches (both hands 1 mm
  // plus the proxy's radius behind the plane: the points lie on it); torque about the wall's origin.
  const std::vector<SceneContact> contacts = shared->contacts();
  ASSERT_EQ(contacts.size(), 2u);
  for (const SceneContact& c : contacts) {
    EXPECT_EQ(c.object, "wall");
    const DeviceView v = s.device(c.device);
    EXPECT_NEAR(c.force.x(), -v.task.wrench.force.x(), 0.02 * std::abs(v.task.wrench.force.x())) << c.device;
    EXPECT_NEAR(c.force.y(), 0.0, 1e-9);
    EXPECT_NEAR(c.point.x(), 0.006, 1e-9) << c.device;
    EXPECT_NEAR((c.torque - (c.point - Eigen::Vector3d(0.006, 0, 0)).cross(c.force)).norm(), 0.0, 1e-9);
  }
  EXPECT_NE(contacts[0].device, contacts[1].device);
  shared->remove("wall");
  EXPECT_TRUE(shared->contacts().empty()) << "a removed object has no contacts";
  s.step(100);  // the render guard's rate limit lets the force down over a few cycles
  for (const char* d : {"v3", "w3"}) EXPECT_EQ(s.device(d).task.wrench.force.norm(), 0.0) << d;
}

// The live view's picture of the session's scene (channel /haptic_scene/scene): every kind of object at its size and
// pose, a mesh's triangles (at most 2000 of a larger one), each device's proxy with its radius (touching or not);
// the still objects again only when they change (or every 2 s), the moving ones and the proxies at every update.
TEST(HapticSceneSession, TheLiveViewDrawsTheScenesObjectsAndEachDevicesProxy) {
  Session s = test::build_test_session(two_devices_on_the_session_scene("scene:\n"));
  SceneService& scene = scene_of(s, 0);
  scene.add(kWallAhead);
  scene.add(R"({"name": "desk", "shape": "box", "size": [0.3, 0.2, 0.02], "position": [0, 0, -0.05]})");
  scene.add(R"({"name": "ball", "shape": "sphere", "radius": 0.02, "position": [0, 0.1, 0]})");
  scene.add(R"({"name": "rail", "shape": "capsule", "radius": 0.005, "length": 0.1, "position": [0, -0.1, 0]})");
  scene.add(R"({"name": "can", "shape": "cylinder", "radius": 0.01, "length": 0.04, "position": [0.1, 0.1, 0],
                "moving": true})");
  std::vector<double> vertices;  // a sheet of 60 x 60 squares: 7200 triangles
  std::vector<std::uint32_t> triangles;
  const int n = 60;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) vertices.insert(vertices.end(), {0.2, 0.001 * i, 0.001 * j});
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const auto v = [&](int a, int b) { return static_cast<std::uint32_t>(a * (n + 1) + b); };
      triangles.insert(triangles.end(), {v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i, j), v(i + 1, j + 1), v(i + 1, j)});
    }
  scene.add_mesh(R"({"name": "sheet", "shape": "mesh"})", vertices, triangles);
  Pose can;
  can.position = Eigen::Vector3d(0.1, 0.12, 0.0);
  scene.move("can", can);
  s.step(2400);  // the hands pressed into the wall

  const SceneDrawing d = scene.drawing(live_view::HapticSceneView::kMaxTriangles);
  ASSERT_EQ(d.objects.size(), 6u);
  EXPECT_EQ(d.objects[1].size, Eigen::Vector3d(0.3, 0.2, 0.02));
  EXPECT_EQ(d.objects[2].size.x(), 0.02);
  EXPECT_EQ(d.objects[3].size, Eigen::Vector3d(0.005, 0.1, 0.0));
  EXPECT_TRUE(d.objects[4].moving);
  EXPECT_EQ(d.objects[4].pose.position, can.position) << "a moving object where it was last moved to";
  EXPECT_EQ(d.objects[5].triangles, 7200u);
  EXPECT_EQ(d.objects[5].corners.size(), 3u * 1800) << "every 4th of 7200 triangles: 1800";
  ASSERT_EQ(d.proxies.size(), 2u);
  for (const SceneProxyDrawing& p : d.proxies) {
    EXPECT_EQ(p.radius, 0.005);
    EXPECT_TRUE(p.touching) << p.device;
    EXPECT_NEAR(p.position.x(), 0.001, 1e-6) << p.device << ": the proxy rests on the wall, its radius before it";
  }

  live_view::HapticSceneView view(scene);
  std::string out;
  const auto entities = [&](const std::string& text, bool first = false) {
    JsonReader json(1 << 16);
    EXPECT_TRUE(json.parse(text)) << json.error();
    std::vector<std::string> ids;
    const JsonReader::Value list = json.root()["entities"];
    for (JsonReader::Value e = list.first(); e; e = e.next()) ids.emplace_back(*e["id"].string());
    std::map<std::string, std::size_t> counts;  // primitives of every entity together
    for (JsonReader::Value e = list.first(); e; e = e.next())
      for (const char* kind : {"cubes", "spheres", "cylinders", "triangles"}) counts[kind] += e[kind].size();
    if (first) {
      EXPECT_EQ(counts["cubes"], 2u) << "the desk and the wall's surface";
      EXPECT_EQ(counts["spheres"], 5u) << "the ball, the rail's two ends, two proxies";
      EXPECT_EQ(counts["cylinders"], 2u) << "the rail and the can";
      EXPECT_EQ(counts["triangles"], 1u) << "the sheet";
    }
    return ids;
  };
  view.scene_update(1, 0, out);
  EXPECT_EQ(entities(out, true),
            (std::vector<std::string>{"haptic_scene/moving", "haptic_scene/still", "haptic_scene/proxies"}));
  view.scene_update(2, 100'000'000, out);
  EXPECT_EQ(entities(out), (std::vector<std::string>{"haptic_scene/moving", "haptic_scene/proxies"}))
      << "nothing still changed";
  scene.remove("ball");
  view.scene_update(3, 200'000'000, out);
  EXPECT_EQ(entities(out).size(), 3u) << "a still object removed: the still ones again";
  view.scene_update(4, 300'000'000, out);
  EXPECT_EQ(entities(out).size(), 2u);
  view.scene_update(5, 2'300'000'000, out);
  EXPECT_EQ(entities(out).size(), 3u) << "every 2 s the still ones again, for a viewer that came late";
}

TEST(HapticSceneSession, ADeviceTakesAnEditOfTheSessionsSceneWithoutAllocating) {
  Session s = test::build_test_session(two_devices_on_the_session_scene("scene:\n"));
  server::DeviceSession& device = test::device_of(s, 0);
  device.activate();
  device.cycle(test::cycle_at(0), 1.0);
  scene_of(s, 0).add(kWallAhead);  // off the loop: the wall's scene made and offered
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "the sanitizer owns malloc";
  testing::AllocationGuard guard;
  for (std::uint64_t k = 1; k <= 3000; ++k) device.cycle(test::cycle_at(k), 1.0);  // the edit taken, the wall felt
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_LT(s.device("v3").task.wrench.force.x(), -2000 * 0.004);
}

// What an engine's edit says, through the scene's service (the doors' way in): refused edits name the object and
// the reason and change nothing; a file named by a client is not opened; a pose that is not one is refused.
std::string refusal(const std::function<void()>& edit) {
  try {
    edit();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(HapticSceneSession, EditsThroughTheScenesServiceAreCheckedAndABadOneChangesNothing) {
  const std::string desk = scene_file("desk-session.yaml", R"(materials:
  wood: {stiffness: 2500, damping: 8}
objects:
  - {name: desk, shape: box, size: [0.3, 0.3, 0.02], position: [0, 0, -0.03], material: wood}
)");
  Session s = test::build_test_session(two_devices_on_the_session_scene("scene: {parameters: {file: " + desk + "}}\n"));
  SceneService& scene = scene_of(s, 0);
  ASSERT_EQ(scene.objects().size(), 1u);
  EXPECT_EQ(scene.objects()[0].name, "desk");
  // A block on the desk, in the file's material, moved by an engine; JSON as the engine socket sends it.
  EXPECT_GT(scene.add(R"({"name": "block", "shape": "box", "size": [0.02, 0.02, 0.02], "position": [0.05, 0, -0.01],
                          "material": "wood", "moving": true})"),
            0u);
  const std::vector<SceneObjectSummary> two = scene.objects();
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[1].shape, "box");
  EXPECT_TRUE(two[1].moving);
  struct Case {
    std::function<void()> edit;
    const char* says;
  };
  Pose nan_pose;
  nan_pose.position.x() = std::numeric_limits<double>::quiet_NaN();
  Pose zero_turn;
  zero_turn.orientation.coeffs().setZero();
  const std::vector<Case> cases{
      {[&] { scene.add("{name: ball, shape: sphere, radius: -0.01}"); }, "object.radius: must be positive"},
      {[&] { scene.add("{name: desk, shape: sphere, radius: 0.01}"); }, "'desk' is taken"},
      {[&] { scene.add("{name: ball, shape: sphere, radius: 0.01, material: steel}"); }, "no material 'steel'"},
      {[&] { scene.add("{name: ball, shape: sphere, radius: 0.01, colour: red}"); }, "object.colour: unknown key"},
      {[&] { scene.add("{name: rock, shape: mesh, file: /etc/passwd}"); }, "a file named by a client is not read"},
      {[&] { scene.add("{name: rock, shape: convex_hull, file: /etc/passwd}"); },
       "a file named by a client is not read"},
      {[&] { scene.add("{name: [unclosed"); }, "the object added:1"},
      {[&] { scene.add(""); }, "no object"},
      {[&] { scene.remove("chair"); }, "no object named 'chair'"},
      {[&] { scene.set_material("desk", "{stiffness: -1}"); }, "material.stiffness: must be positive"},
      {[&] { scene.set_material("chair", "wood"); }, "no object named 'chair'"},
      {[&] { scene.move("desk", Pose{}); }, "'desk' was not made a moving object"},
      {[&] { scene.move("block", nan_pose); }, "is not a pose"},
      {[&] { scene.move("block", zero_turn); }, "is not a pose"},
  };
  for (const Case& c : cases) {
    const std::string said = refusal(c.edit);
    EXPECT_NE(said.find(c.says), std::string::npos) << "expected '" << c.says << "', got: " << said;
  }
  EXPECT_EQ(scene.objects().size(), 2u);  // nothing changed
  s.step(200);
  for (const char* d : {"v3", "w3"}) EXPECT_TRUE(s.device(d).fault.empty()) << d;
  // Good edits: a material by name or in place, a move, a removal.
  scene.set_material("block", "{stiffness: 3000, static_friction: 0.4}");
  scene.set_material("block", "wood");
  Pose there;
  there.position = Eigen::Vector3d(0.06, 0, -0.01);
  scene.move("block", there);
  scene.remove("block");
  EXPECT_EQ(scene.objects().size(), 1u);
}

TEST(HapticSceneSession, TheSessionsSceneFileIsCheckedAtStartAndAModelWithoutSceneNeedsTheSection) {
  const std::string broken =
      scene_file("broken-session.yaml", "objects:\n  - name: ball\n    shape: sphere\n    radius: -0.02\n");
  const std::string error =
      test::config_error_of(two_devices_on_the_session_scene("scene: {parameters: {file: " + broken + "}}\n"));
  EXPECT_NE(error.find("scene.parameters.file"), std::string::npos) << error;
  EXPECT_NE(error.find("broken-session.yaml:4: objects[0].radius: must be positive"), std::string::npos) << error;
  const std::string unknown =
      test::config_error_of(two_devices_on_the_session_scene("scene: {parameters: {flie: x.yaml}}\n"));
  EXPECT_NE(unknown.find("scene.parameters.flie"), std::string::npos) << unknown;
  const std::string none = test::config_error_of(two_devices_on_the_session_scene(""));
  EXPECT_NE(none.find("the session has no scene section"), std::string::npos) << none;
}

}  // namespace
}  // namespace hapticd::server
