// hapticd-mujoco-scene: a physics engine that puts its world into the server's haptic scene (docs/haptic-scene.md,
// "A block pushed in MuJoCo"). It loads an MJCF model, claims the session's scene over DDS and adds every geom of
// the model as an object - the world's geoms still, the other bodies' geoms `moving` - then, at its frame rate,
// asks the server what the hands do to the objects, applies those forces to the bodies, steps MuJoCo for one frame
// and moves the objects to where MuJoCo put them. The server renders the objects at loop rate (their poses played
// back between frames), so nothing of the engine is in the haptic loop: the hand feels the block and pushes it,
// MuJoCo moves it. The model's origin is put at a device's handle as it starts (--device), so a model is written
// about the hand. At its end it removes what it added.
#include <fmt/format.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "hapticd/client/client.hpp"

namespace {

std::atomic<bool> stopping{false};

void on_mujoco_error(const char* message) {
  const std::string line = fmt::format("hapticd-mujoco-scene: MuJoCo error: {}\n", message);
  (void)!write(STDERR_FILENO, line.data(), line.size());
  std::_Exit(2);
}

using hapticd::Pose;
using hapticd::client::Client;
using hapticd::client::SceneClient;

struct Settings {
  std::string model, device, id = "mujoco-scene", material = R"({"stiffness": 2500, "damping": 5})";
  int domain = 0;
  double rate_hz = 60.0, duration_s = 0.0, wait_s = 20.0;
  std::vector<std::string> watch;
};

// One geom as a scene object: its name there, whether it moves, and its body.
struct Mirrored {
  int geom = 0, body = 0;
  std::string name;
  bool moving = false;
};

// The geom's pose in the session's world: MuJoCo's, shifted by the model's origin.
Pose pose_of(const mjModel*, const mjData* d, int geom, const Eigen::Vector3d& origin) {
  Pose p;
  p.position = origin + Eigen::Vector3d(d->geom_xpos[3 * geom], d->geom_xpos[3 * geom + 1], d->geom_xpos[3 * geom + 2]);
  double q[4];
  mju_mat2Quat(q, d->geom_xmat + 9 * geom);
  p.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
  return p;
}

// The object's JSON as the scene file writes one; empty for a geom type the scene has no shape for.
std::string object_json(const mjModel* m, int g, const Mirrored& o, const Pose& pose, const std::string& material) {
  const double* s = m->geom_size + 3 * g;
  std::string shape;
  switch (m->geom_type[g]) {
    case mjGEOM_PLANE:
      shape = R"("shape": "plane")";
      break;
    case mjGEOM_SPHERE:
      shape = fmt::format(R"("shape": "sphere", "radius": {})", s[0]);
      break;
    case mjGEOM_CAPSULE:
      shape = fmt::format(R"("shape": "capsule", "radius": {}, "length": {})", s[0], 2 * s[1]);
      break;
    case mjGEOM_CYLINDER:
      shape = fmt::format(R"("shape": "cylinder", "radius": {}, "length": {})", s[0], 2 * s[1]);
      break;
    case mjGEOM_BOX:
      shape = fmt::format(R"("shape": "box", "size": [{}, {}, {}])", 2 * s[0], 2 * s[1], 2 * s[2]);
      break;
    default:
      return {};
  }
  const Eigen::Quaterniond& q = pose.orientation;
  return fmt::format(R"({{"name": "{}", {}, "position": [{}, {}, {}], "quaternion": [{}, {}, {}, {}], )"
                     R"("material": {}, "moving": {}}})",
                     o.name, shape, pose.position.x(), pose.position.y(), pose.position.z(), q.w(), q.x(), q.y(), q.z(),
                     material, o.moving ? "true" : "false");
}

int run(const Settings& s) {
  mju_user_error = on_mujoco_error;
  char error[1000] = "";
  mjModel* m = mj_loadXML(s.model.c_str(), nullptr, error, sizeof error);
  if (m == nullptr) {
    fmt::print(stderr, "hapticd-mujoco-scene: {}: {}\n", s.model, error);
    return 2;
  }
  mjData* d = mj_makeData(m);
  mj_forward(m, d);

  Client client({s.id, s.domain});
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  if (!s.device.empty()) {
    const auto info = client.wait_for_device(s.device, hapticd::client::Timeout(s.wait_s), true);
    if (!info || !info->start_pose) {
      fmt::print(stderr, "hapticd-mujoco-scene: no device '{}' within {} s\n", s.device, s.wait_s);
      return 2;
    }
    origin = info->start_pose->position;
  }
  SceneClient& scene = client.scene();
  auto reply = scene.claim(hapticd::client::Timeout(s.wait_s));
  if (!reply.accepted) {
    fmt::print(stderr, "hapticd-mujoco-scene: the scene: {}\n", reply.message);
    return 2;
  }

  // Every geom the scene has a shape for, named as in the model (unnamed: geom<N>).
  std::vector<Mirrored> objects;
  std::map<std::string, std::size_t> by_name;
  for (int g = 0; g < m->ngeom; ++g) {
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    Mirrored o{g, m->geom_bodyid[g], name != nullptr && *name != '\0' ? name : fmt::format("geom{}", g),
               m->body_weldid[m->geom_bodyid[g]] != 0};
    const std::string json = object_json(m, g, o, pose_of(m, d, g, origin), s.material);
    if (json.empty()) {
      fmt::print("hapticd-mujoco-scene: geom '{}' left out (no scene shape for its type)\n", o.name);
      continue;
    }
    reply = scene.add(json);
    if (!reply.accepted) {
      fmt::print(stderr, "hapticd-mujoco-scene: geom '{}': {}\n", o.name, reply.message);
      (void)scene.release();
      return 2;
    }
    by_name[o.name] = objects.size();
    objects.push_back(o);
  }
  fmt::print(
      "hapticd-mujoco-scene: {} objects in the scene ({} moving), the model's origin at [{:.4f}, {:.4f}, {:.4f}]\n",
      objects.size(), std::count_if(objects.begin(), objects.end(), [](const Mirrored& o) { return o.moving; }),
      origin.x(), origin.y(), origin.z());

  std::vector<Eigen::Vector3d> start(static_cast<std::size_t>(m->nbody));
  for (int b = 0; b < m->nbody; ++b) start[b] = Eigen::Vector3d(d->xpos[3 * b], d->xpos[3 * b + 1], d->xpos[3 * b + 2]);
  const double frame_s = 1.0 / s.rate_hz;
  const int steps = std::max(1, static_cast<int>(std::lround(frame_s / m->opt.timestep)));
  const auto t0 = std::chrono::steady_clock::now();
  auto next = t0;
  std::uint64_t frames = 0, pushed_frames = 0;
  double push_sum = 0.0, second_push = 0.0;
  int second_frames = 0;
  while (!stopping.load() &&
         (s.duration_s <= 0.0 || std::chrono::steady_clock::now() - t0 < std::chrono::duration<double>(s.duration_s))) {
    // The hands' forces on the moving objects, held over the frame.
    mju_zero(d->qfrc_applied, m->nv);
    const auto contacts = scene.contacts();
    double push = 0.0;
    for (const auto& c : contacts.contacts) {
      const auto found = by_name.find(c.object_name);
      if (found == by_name.end() || !objects[found->second].moving) continue;
      mjtNum force[3] = {c.force.x(), c.force.y(), c.force.z()}, torque[3] = {0, 0, 0};
      const Eigen::Vector3d at = c.point - origin;
      mjtNum point[3] = {at.x(), at.y(), at.z()};
      mj_applyFT(m, d, force, torque, point, objects[found->second].body, d->qfrc_applied);
      push += c.force.norm();
    }
    for (int k = 0; k < steps; ++k) mj_step(m, d);
    for (const Mirrored& o : objects)
      if (o.moving) (void)scene.move(o.name, pose_of(m, d, o.geom, origin));
    ++frames;
    if (push > 0.0) {
      ++pushed_frames;
      push_sum += push;
    }
    second_push += push;
    if (++second_frames == static_cast<int>(std::lround(s.rate_hz))) {
      std::string where;
      for (const std::string& b : s.watch) {
        const int id = mj_name2id(m, mjOBJ_BODY, b.c_str());
        if (id >= 0)
          where += fmt::format(
              " {} {:+.1f} mm", b,
              1e3 * (Eigen::Vector3d(d->xpos[3 * id], d->xpos[3 * id + 1], d->xpos[3 * id + 2]) - start[id]).x());
      }
      fmt::print("t {:.1f} s: pushed with {:.2f} N (the second's mean){}\n", d->time, second_push / second_frames,
                 where);
      second_push = 0.0;
      second_frames = 0;
    }
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(frame_s));
    std::this_thread::sleep_until(next);
  }
  for (const std::string& b : s.watch) {
    const int id = mj_name2id(m, mjOBJ_BODY, b.c_str());
    if (id < 0) continue;
    const Eigen::Vector3d moved =
        Eigen::Vector3d(d->xpos[3 * id], d->xpos[3 * id + 1], d->xpos[3 * id + 2]) - start[id];
    fmt::print("body '{}' moved [{:+.1f}, {:+.1f}, {:+.1f}] mm\n", b, 1e3 * moved.x(), 1e3 * moved.y(),
               1e3 * moved.z());
  }
  fmt::print("{} frames at {} Hz, pushed in {} of them ({:.2f} N on average then); {} refused moves\n", frames,
             s.rate_hz, pushed_frames, pushed_frames > 0 ? push_sum / static_cast<double>(pushed_frames) : 0.0,
             scene.refused_moves());
  for (const Mirrored& o : objects) (void)scene.remove(o.name);
  (void)scene.release();
  mj_deleteData(d);
  mj_deleteModel(m);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hapticd-mujoco-scene: a MuJoCo world in the server's haptic scene, pushed by the hands"};
  Settings s;
  app.add_option("model", s.model, "the MJCF model: its geoms become the scene's objects")->required();
  app.add_option("--device", s.device, "put the model's origin at this device's handle as it starts");
  app.add_option("--id", s.id, "client id (the scene's owner)");
  app.add_option("--domain", s.domain, "DDS domain")->check(CLI::Range(0, 230));
  app.add_option("--rate", s.rate_hz, "frames a second: contacts in, a step, poses out")
      ->check(CLI::Range(1.0, 1000.0));
  app.add_option("--duration", s.duration_s, "stop after this many seconds (0: until SIGINT/SIGTERM)");
  app.add_option("--wait", s.wait_s, "how long to wait for the device and the scene's claim");
  app.add_option("--material", s.material, "every object's material (JSON, as the scene file writes one)");
  app.add_option("--watch", s.watch, "print these bodies' travel every second and at the end");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (std::getenv("HAPTICD_PARSE_ONLY") != nullptr) {
    std::fprintf(stderr, "hapticd-mujoco-scene: the command line parsed (HAPTICD_PARSE_ONLY is set: nothing run)\n");
    return 0;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::signal(SIGINT, [](int) { stopping.store(true); });
  std::signal(SIGTERM, [](int) { stopping.store(true); });
  try {
    return run(s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapticd-mujoco-scene: %s\n", e.what());
    return 2;
  }
}
