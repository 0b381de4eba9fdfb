// The haptic scene's proxy on the loop (docs/haptic-scene.md, "Measured"): one update() - contact planes, the
// projection, the sweeps, friction and the force - while the goal strokes a sphere of 5 cm radius 3 mm deep at
// 0.2 m/s (2 kHz) across its surface, for a mesh sphere (icospheres of 1 280, 81 920 and 1 310 720 triangles;
// the structure's build time too) and, side by side, the analytic sphere: the reference the figures are read
// against. Each update timed on the monotonic clock; 20 000 of them after 2 000 to settle.
//   scene_proxy_update [LEVELS...]   (icosphere subdivision levels; default 3 6 8)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <vector>

#include "hapticd/scene/mesh_file.hpp"
#include "hapticd/scene/proxy.hpp"

namespace {

using namespace hapticd::scene;
using Clock = std::chrono::steady_clock;

struct Figures {
  double p50, p99, max;
};

Figures stroke(const Scene& scene) {
  const double radius = 0.05, r = 0.005;
  GodObject proxy;
  ProxySettings settings;
  settings.radius_m = r;
  proxy.configure(settings, scene);
  auto goal_at = [&](int k) -> Eigen::Vector3d {
    // A path over the sphere: along a slowly turning great circle, 0.2 m/s at 2 kHz (0.1 mm a cycle).
    const double s = k * 1e-4 / (radius + r - 0.003);
    const double tilt = 0.3 * std::sin(k * 1e-4);
    return Eigen::Vector3d(std::cos(s) * std::cos(tilt), std::sin(s) * std::cos(tilt), std::sin(tilt)) *
           (radius + r - 0.003);
  };
  proxy.reset(goal_at(0) * 2.0);
  for (int k = 0; k < 200; ++k) proxy.update(goal_at(0) * (2.0 - k / 200.0), Eigen::Vector3d::Zero());
  std::vector<double> us;
  us.reserve(20000);
  for (int k = 0; k < 22000; ++k) {
    const Eigen::Vector3d g = goal_at(k);
    const auto t0 = Clock::now();
    const ProxyState& s = proxy.update(g, Eigen::Vector3d(0.2, 0, 0));
    const double t = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
    if (k >= 2000) us.push_back(t);
    if (s.contact_count == 0 && k > 10) {
      std::fprintf(stderr, "lost contact at %d\n", k);
      std::exit(1);
    }
  }
  std::sort(us.begin(), us.end());
  return {us[us.size() / 2], us[us.size() * 99 / 100], us.back()};
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> levels;
  for (int i = 1; i < argc; ++i) levels.push_back(std::atoi(argv[i]));
  if (levels.empty()) levels = {3, 6, 8};
  SceneObject ball;
  ball.name = "ball";
  ball.shape.kind = ShapeKind::sphere;
  ball.shape.radius = 0.05;
  const Figures reference = stroke(Scene{{ball}});
  std::printf(
      "| sphere | build (ms) | update p50 (us) | p99 (us) | max (us) | p50 / analytic |\n|---|---|---|---|---|---|\n");
  std::printf("| analytic (the reference) | - | %.2f | %.2f | %.1f | 1 |\n", reference.p50, reference.p99,
              reference.max);
  for (int level : levels) {
    SceneObject mesh;
    mesh.name = "mesh";
    mesh.shape.kind = ShapeKind::mesh;
    TriangleMeshData data = icosphere_mesh(level, 0.05);
    const std::size_t triangles = data.triangles.size();
    const auto t0 = Clock::now();
    mesh.shape.mesh = MeshShape::build(std::move(data), "sphere");
    const double build_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const Figures f = stroke(Scene{{mesh}});
    std::printf("| %zu triangles | %.0f | %.2f | %.2f | %.1f | %.1f |\n", triangles, build_ms, f.p50, f.p99, f.max,
                f.p50 / reference.p50);
    std::fflush(stdout);
  }
  return 0;
}
