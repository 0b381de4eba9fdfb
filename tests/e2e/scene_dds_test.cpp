// The session's haptic scene over DDS (docs/haptic-scene.md, "Engines edit the scene"): an engine on the client
// library (Client::scene(), a participant of its own) claims the scene of a server served as `hapticd` serves it, on
// a test domain of its own with the loopback-only configuration, in real time (the scene needs no engine in the
// loop, so nothing waits for the engine's answers). The simulated operator pushes 15 N into what the engine adds.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "e2e/dds_server_rig.hpp"
#include "hapticd/client/scene_client.hpp"
#include "support/test_paths.hpp"

namespace hapticd::server {
namespace {

using client::Client;
using client::SceneReply;
using e2e::Server;
using namespace std::chrono_literals;

// The simulated ViSHaRD3 held by the operator's hand, rendering the session's scene (empty at the start) in
// impedance display, its models' origin at the handle's start.
std::string scene_session(int domain) {
  return "server: {clock: realtime, seed: 5, realtime_priority: 0, lock_memory: false, duration_s: 60}\n"
         "dds: {domain_id: " +
         std::to_string(domain) + "}\nscene:\ndevices:\n  - name: v3\n" +
         R"(    device:
      plugin: sim
      parameters:
        urdf: )" +
         test::source_dir() +
         R"(/config/urdf/vishard3.urdf
        initial_position: [-0.3, 1.6, 0.0]
        passive_gimbal: true
        sensor_accelerations: true
        attachment: operator
        operator_grasp: 0.7
    virtual_model:
      plugin: haptic_scene
      parameters: {origin: handle, proxy_radius_m: 0.005, max_stiffness_n_per_m: 4000}
    controller:
      plugin: impedance
      parameters: {task: translation, force_gain: 0.0}
    safety: {)" +
         e2e::kRealtimeWatchdogs + "}\n";
}

// 2 cm ahead of the handle's start along +x, 3000 N/m.
constexpr const char* kWall = R"({"name": "wall", "shape": "plane", "position": [0.02, 0, 0], "normal": [-1, 0, 0],
  "material": {"stiffness": 3000, "damping": 5}})";

double handle_x(Server& server) {
  const auto& x = server.recording().position();
  return x.empty() ? 0.0 : x.back().x() - x.front().x();
}

// Waits (at most `limit`) until `done`; true when it came.
template <class F>
bool eventually(F&& done, std::chrono::milliseconds limit = 5000ms) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(10ms);
  }
  return true;
}

// A flat sheet of n x n squares (2 n^2 triangles) in the plane x = at, 6 cm wide, facing -x.
void sheet(double at, int n, std::vector<double>& vertices, std::vector<std::uint32_t>& triangles) {
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) vertices.insert(vertices.end(), {at, -0.03 + 0.06 * i / n, -0.03 + 0.06 * j / n});
  const auto v = [n](int i, int j) { return static_cast<std::uint32_t>(i * (n + 1) + j); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      triangles.insert(triangles.end(), {v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i, j), v(i + 1, j + 1), v(i + 1, j)});
}

TEST(SceneDds, AnEngineOwnsTheScenePushedByTheHandAndEveryBadEditIsRefused) {
  Server server(scene_session(164));
  Client engine({"scene-engine", 164});
  Client intruder({"intruder", 164});
  server.start();
  ASSERT_TRUE(engine.wait_for_device("v3", 10s, true));
  client::SceneClient& scene = engine.scene();
  client::SceneClient& other = intruder.scene();

  // Before the claim nobody edits; one owner at a time.
  SceneReply r = scene.add(kWall, 5s);
  ASSERT_TRUE(r.answered) << r.message;
  EXPECT_FALSE(r.accepted);
  EXPECT_EQ(r.message, "claim the scene first");
  r = scene.claim(5s);
  ASSERT_TRUE(r.accepted) << r.message;
  r = other.claim(5s);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("claimed by 'scene-engine'"), std::string::npos) << r.message;
  r = other.add(kWall, 5s);
  EXPECT_FALSE(r.accepted) << "an intruder's add";

  // The wall holds the operator's 15 N push: through the 5 mm proxy the handle rests 15 N / 3000 N/m into it.
  r = scene.add(kWall, 5s);
  ASSERT_TRUE(r.accepted) << r.message;
  ASSERT_TRUE(engine.operator_command("v3", "push", {15.0, 0.0, 0.0, 0.3}, 5s).accepted);
  std::this_thread::sleep_for(1500ms);
  // The hand pushes through the operator's arm: it presses the wall with what its grasp passes on (about 9 N); the
  // handle rests where the wall's spring holds that, behind the plane by the proxy's radius.
  const double held = handle_x(server), pressed = -server.recording().force().back().x();
  std::printf("the wall at 20 mm holds the push: the handle rests at %.2f mm, pressing %.2f N\n", 1e3 * held, pressed);
  EXPECT_GT(pressed, 5.0);
  EXPECT_NEAR(held, 0.02 - 0.005 + pressed / 3000, 0.0005);

  // Two-way: the hand pushes the wall with the force it feels, reversed.
  r = scene.contacts(5s);
  ASSERT_TRUE(r.accepted) << r.message;
  ASSERT_EQ(r.contacts.size(), 1u);
  const Eigen::Vector3d felt = server.recording().force().back();
  std::printf("contacts: v3 pushes '%s' with %.2f N (the hand feels %.2f N)\n", r.contacts[0].object_name.c_str(),
              r.contacts[0].force.x(), felt.x());
  EXPECT_EQ(r.contacts[0].device, "v3");
  EXPECT_EQ(r.contacts[0].object_name, "wall");
  EXPECT_NEAR(r.contacts[0].force.x(), -felt.x(), 0.05 * pressed);
  EXPECT_NEAR(r.contacts[0].force.y(), 0.0, 1e-6);

  // Bad edits, each refused with its reason, and the wall holds on.
  const struct {
    const char* what;
    std::string object;
    const char* reason;
  } bad[] = {
      {"not JSON", "{\"name\": ", "must be a JSON object"},
      {"YAML with an alias", "a: &x [1, 2]\nb: *x\n", "must be a JSON object"},
      {"a JSON array", "[1, 2]", "must be a JSON object"},
      {"a negative radius", R"({"name": "ball", "shape": "sphere", "radius": -0.01})", "radius"},
      {"a mesh file", R"({"name": "rock", "shape": "mesh", "file": "/etc/passwd"})", "is not read"},
      {"a name taken", kWall, "wall"},
      {"an upload not made", R"({"name": "rock", "shape": "mesh", "upload": "nothing"})", "no finished upload"},
      {"an upload that is not a name", R"({"name": "rock", "shape": "mesh", "upload": 7})", "upload"},
  };
  for (const auto& b : bad) {
    r = scene.add(b.object, 5s);
    ASSERT_TRUE(r.answered) << b.what;
    EXPECT_FALSE(r.accepted) << b.what;
    EXPECT_NE(r.message.find(b.reason), std::string::npos) << b.what << ": " << r.message;
  }
  r = scene.set_material("wall", "a: &x [1]\nb: *x", 5s);
  EXPECT_FALSE(r.accepted) << "a material in YAML";
  r = scene.set_material("nothing", "steel", 5s);
  EXPECT_FALSE(r.accepted) << "a material of an unknown object";
  r = scene.add(std::string(5000, ' '), 5s);
  EXPECT_FALSE(r.answered) << "a text over the wire's bound is not sent";
  // Moves are not answered; a refused one is, and counted.
  EXPECT_TRUE(scene.move("wall", Pose{}));  // the wall is not `moving`
  Pose nowhere;
  nowhere.position.x() = std::nan("");
  EXPECT_TRUE(other.move("wall", nowhere));  // not the owner
  EXPECT_TRUE(eventually([&] { return scene.refused_moves() == 1 && other.refused_moves() == 1; }));
  std::printf("refused moves: '%s', '%s'\n", scene.last_refusal().c_str(), other.last_refusal().c_str());
  EXPECT_NE(other.last_refusal().find("claimed by"), std::string::npos);
  EXPECT_NEAR(handle_x(server), held, 0.0015) << "the wall held through the bad edits";

  // A material at a third of the stiffness: the handle goes further in, as far as the softer spring lets it.
  r = scene.set_material("wall", R"({"stiffness": 1000, "damping": 5})", 5s);
  ASSERT_TRUE(r.accepted) << r.message;
  std::this_thread::sleep_for(1500ms);
  const double soft = handle_x(server), soft_pressed = -server.recording().force().back().x();
  std::printf("at 1000 N/m: the handle rests at %.2f mm, pressing %.2f N\n", 1e3 * soft, soft_pressed);
  EXPECT_GT(soft, held + 0.002);
  EXPECT_NEAR(soft, 0.02 - 0.005 + soft_pressed / 1000, 0.0005);

  // A mesh uploaded in parts (3200 triangles, 1681 vertices: four parts), 1 mm behind the wall, holds the push
  // once the wall is gone.
  std::vector<double> vertices;
  std::vector<std::uint32_t> triangles;
  sheet(0.021, 40, vertices, triangles);
  r = scene.add_mesh(R"({"name": "sheet", "shape": "mesh", "material": {"stiffness": 3000, "damping": 5}})", vertices,
                     triangles, 10s);
  ASSERT_TRUE(r.accepted) << r.message;
  ASSERT_TRUE(scene.remove("wall", 5s).accepted);
  std::this_thread::sleep_for(1500ms);
  const double on_sheet = handle_x(server), sheet_pressed = -server.recording().force().back().x();
  std::printf("the uploaded sheet at 21 mm holds the push: the handle rests at %.2f mm, pressing %.2f N\n",
              1e3 * on_sheet, sheet_pressed);
  EXPECT_GT(sheet_pressed, 5.0);
  EXPECT_NEAR(on_sheet, 0.021 - 0.005 + sheet_pressed / 3000, 0.0005);
  // A mesh whose triangle names a vertex it lacks: refused at its add, naming the object.
  r = scene.add_mesh(R"({"name": "broken", "shape": "mesh"})", std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0},
                     std::vector<std::uint32_t>{0, 1, 7}, 5s);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("broken"), std::string::npos) << r.message;

  // The list comes in pages of 32: 40 balls far away and the sheet.
  std::this_thread::sleep_for(1000ms);  // the rate limit's allowance back (50 a second)
  for (int i = 0; i < 40; ++i) {
    const std::string ball = R"({"name": "ball)" + std::to_string(i) +
                             R"(", "shape": "sphere", "radius": 0.01, "position": [0.5, )" + std::to_string(0.03 * i) +
                             R"(, 0], "moving": true})";
    ASSERT_TRUE(scene.add(ball, 5s).accepted) << i;
  }
  r = scene.objects(5s);
  ASSERT_TRUE(r.accepted) << r.message;
  ASSERT_EQ(r.objects.size(), 41u);
  EXPECT_EQ(r.objects[0].name, "sheet");
  EXPECT_EQ(r.objects[0].shape, "mesh");
  EXPECT_EQ(r.objects[0].triangles, 3200u);
  EXPECT_EQ(r.objects[40].name, "ball39");
  EXPECT_TRUE(r.objects[40].moving);
  EXPECT_NEAR(r.objects[40].pose.position.y(), 0.03 * 39, 1e-9);
  // A flood of adds is rate-limited: refused and counted, the loop on.
  int limited = 0;
  for (int i = 0; i < 80; ++i) {
    r = scene.add(R"({"name": "flood)" + std::to_string(i) + R"(", "shape": "sphere", "radius": 0.01,
                     "position": [-0.5, 0, 0]})",
                  5s);
    limited += r.message.find("a second") != std::string::npos ? 1 : 0;
  }
  EXPECT_GT(limited, 0);
  ASSERT_NE(server.bridge().gate().scene(), nullptr);
  EXPECT_GE(server.bridge().gate().scene()->rate_limited(), static_cast<std::uint64_t>(limited));
  // Moves at 60 Hz go through unanswered.
  for (int k = 0; k < 30; ++k) {
    Pose p;
    p.position = Eigen::Vector3d(0.5, 0.0, 0.001 * k);
    EXPECT_TRUE(scene.move("ball0", p));
    std::this_thread::sleep_for(16ms);
  }
  EXPECT_EQ(scene.refused_moves(), 1u);

  // The claim ends with its participant: a new engine claims once the old one is gone.
  {
    Client brief({"brief-engine", 164});
    ASSERT_TRUE(scene.release(5s).accepted);
    ASSERT_TRUE(brief.scene().claim(5s).accepted);
    EXPECT_FALSE(other.claim(5s).accepted);
  }
  EXPECT_TRUE(eventually([&] { return other.claim(2s).accepted; }, 10000ms)) << "the gone engine's claim ended";
  std::this_thread::sleep_for(500ms);
  r = other.remove("ball0", 5s);
  EXPECT_TRUE(r.accepted) << "the new owner edits: " << r.message;
  EXPECT_EQ(server.device().status().fault(), DeviceFault::none);
  server.stop();
}

// A server without a scene stays silent (another server on the domain may have the scene an engine edits); the client
// says what is missing.
TEST(SceneDds, AServerWithoutASceneDoesNotAnswerAndTheClientSaysWhatIsMissing) {
  Server server(e2e::session_yaml(165, 30.0, "constant", "[0.0, 0.0, 0.0]", "realtime"));
  Client engine({"scene-engine", 165});
  server.start();
  ASSERT_TRUE(engine.wait_for_device("v3", 10s, true));
  const SceneReply r = engine.scene().claim(1.5s);
  EXPECT_FALSE(r.answered);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("no server on this DDS domain has a haptic scene"), std::string::npos) << r.message;
  server.stop();
}

}  // namespace
}  // namespace hapticd::server
