// Meshes in the haptic scene (scene/mesh.hpp, scene/mesh_file.hpp): a flat mesh floor feels as the analytic plane
// of the same material; stroking a tessellated sphere with force shading keeps the force within 1 degree of the
// sphere's true normal without steps at the edges (without shading it is off by up to the facets' angle); an
// open 0-thickness sheet is not passed at 1 or 10 m/s; the files: STL, OBJ, PLY read, and every kind of bad file
// refused with its name; a mesh in a scene file; no allocation on the loop.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "hapticd/scene/mesh_file.hpp"
#include "hapticd/scene/proxy.hpp"
#include "hapticd/scene/scene_file.hpp"
#include "hapticd/testing/allocation_guard.hpp"

namespace hapticd::scene {
namespace {

SceneObject mesh_object(const std::string& name, TriangleMeshData data, double k = 2000.0) {
  SceneObject o;
  o.name = name;
  o.shape.kind = ShapeKind::mesh;
  o.shape.mesh = MeshShape::build(std::move(data), name);
  o.material.stiffness_n_per_m = k;
  o.material.damping_n_s_per_m = 0.0;
  return o;
}

struct Rig {
  Scene scene;
  GodObject proxy;
  Eigen::Vector3d goal;
  Rig(Scene s, Eigen::Vector3d start, double radius = 0.005, bool shading = true) : scene(std::move(s)), goal(start) {
    ProxySettings settings;
    settings.radius_m = radius;
    settings.force_shading = shading;
    proxy.configure(settings, scene);
    proxy.reset(goal);
  }
  const ProxyState& move(const Eigen::Vector3d& to, double speed = 0.1) {
    const int steps = std::max(1, static_cast<int>(std::ceil((to - goal).norm() / (speed * 5e-4))));
    const Eigen::Vector3d from = goal;
    for (int k = 1; k <= steps; ++k) {
      goal = from + (to - from) * (static_cast<double>(k) / steps);
      proxy.update(goal, Eigen::Vector3d::Zero());
    }
    return proxy.update(goal, Eigen::Vector3d::Zero());
  }
};

// A dense mesh with friction: the proxy rests on a ball of 81 920 triangles (facets of 0.2 mm) pressed 2 mm deep,
// its friction holding it up to 0.8 mm from where it would slide to - four facets. Before the frictionless point
// was kept from one update to the next, each update's frictionless solve started at the proxy and crossed one
// facet an iteration: both passes ran to max_iterations at every update of the hold (a 1.3 million-triangle pebble
// at 4 kHz then overran the loop ten times in a row and the device went to its safe state), and a pass ended only
// when the proxy moved less than a nanometre, which rolling over a dense mesh's rounded edges takes many
// iterations to reach. Now the solve converges in every update, in about three iterations a pass, while the stick
// and the slip stay what they were.
TEST(SceneMesh, FrictionOnADenseMeshConvergesInAFewIterationsAnUpdate) {
  SceneObject ball = mesh_object("ball", icosphere_mesh(6, 0.01), 3000.0);
  ball.material.static_friction = 0.4;
  ball.material.dynamic_friction = 0.3;
  Rig rig({{ball}}, {0.0, 0.0, 0.02});
  rig.move({0.0, 0.0, 0.013}, 0.05);  // 2 mm deep on the top (ball 10 mm + proxy 5 mm)
  int most = 0, updates = 0, total = 0;
  bool slid = false;
  double held = 0.0;
  for (int k = 1; k <= 2000; ++k) {  // then 1 s sideways at 2 mm/s: it sticks, then slides
    rig.goal = Eigen::Vector3d(2e-3 * k / 2000.0, 0.0, 0.013);
    const ProxyState& s = rig.proxy.update(rig.goal, Eigen::Vector3d::Zero());
    most = std::max(most, s.iterations);
    total += s.iterations;
    ++updates;
    slid = slid || s.sliding;
    if (!s.sliding) held = std::max(held, std::abs(s.force.x()));
    ASSERT_GT(s.contact_count, 0) << "lost the ball at update " << k;
  }
  // Every update's solve converged (neither pass ran to its max_iterations), in about three iterations a pass.
  EXPECT_LT(most, 2 * ProxySettings{}.max_iterations);
  EXPECT_LE(static_cast<double>(total) / updates, 7.0);
  EXPECT_TRUE(slid);
  // It stuck until the tangential force reached the static cone (0.4 x the normal force, about 6 N x 0.4).
  EXPECT_GT(held, 1.5);
  EXPECT_EQ(updates, 2000);
}

TEST(SceneMesh, AFlatMeshFloorFeelsAsTheAnalyticPlaneOfTheSameMaterial) {
  SceneObject plane;
  plane.name = "plane";
  plane.shape.kind = ShapeKind::plane;
  plane.material.stiffness_n_per_m = 2000.0;
  plane.material.damping_n_s_per_m = 0.0;
  Rig mesh({{mesh_object("floor", grid_mesh(40, 0.2))}}, {0.0, 0.0, 0.02});
  Rig analytic({{plane}}, {0.0, 0.0, 0.02});
  int checked = 0;
  for (double x = -0.05; x <= 0.05; x += 0.0123)
    for (double y = -0.05; y <= 0.05; y += 0.0171)
      for (double depth : {0.001, 0.004, 0.009}) {
        const Eigen::Vector3d to(x, y, 0.005 - depth);
        const ProxyState& a = mesh.move(to);
        const ProxyState& b = analytic.move(to);
        ASSERT_NEAR(a.force.z(), b.force.z(), 0.05 * b.force.z()) << x << " " << y << " " << depth;
        ASSERT_NEAR(a.force.z(), 2000.0 * depth, 1e-3);
        ASSERT_LT(std::hypot(a.force.x(), a.force.y()), 1e-3);  // (the projection's tolerance: well under 1 um)
        mesh.move({x, y, 0.02});
        analytic.move({x, y, 0.02});
        ++checked;
      }
  EXPECT_GT(checked, 100);
}

// The angle between the force and the sphere's true normal at the proxy, over a stroke down a meridian at 3 mm
// depth; and the largest change of that angle from one sample to the next (a step at an edge).
std::pair<double, double> stroke(bool shading) {
  const double radius = 0.05, r = 0.005;
  Rig rig({{mesh_object("ball", icosphere_mesh(3, radius), 1500.0)}}, {0.0, 0.013, radius + 0.03}, r, shading);
  double worst = 0.0, step = 0.0, last = -1.0;
  for (int k = 0; k <= 2000; ++k) {
    const double a = std::numbers::pi / 2 * (1.0 - k / 2000.0) * 0.9;
    const Eigen::Vector3d direction = Eigen::Vector3d(std::cos(a), 0.26, std::sin(a)).normalized();
    rig.move((radius + r - 0.003) * direction, 0.2);
    const ProxyState& s = rig.proxy.state();
    const Eigen::Vector3d normal = s.proxy.normalized();
    const double angle = std::acos(std::min(1.0, s.force.normalized().dot(normal))) * 180.0 / std::numbers::pi;
    if (k > 20) {
      worst = std::max(worst, angle);
      if (last >= 0.0) step = std::max(step, std::abs(angle - last));
    }
    last = angle;
  }
  return {worst, step};
}

TEST(SceneMesh, StrokingATessellatedSphereWithForceShadingTheForceFollowsItsTrueNormal) {
  const auto [shaded, shaded_step] = stroke(true);
  const auto [flat, flat_step] = stroke(false);
  std::printf("force against the sphere's normal: shaded %.3f deg (largest step %.4f), flat %.3f deg (step %.4f)\n",
              shaded, shaded_step, flat, flat_step);
  EXPECT_LT(shaded, 1.0) << "1280 triangles, shaded";
  EXPECT_LT(shaded_step, 0.1) << "no step at the edges";
  EXPECT_GT(flat, 2.0) << "without shading, the facets' angle shows";
  EXPECT_GT(flat_step, 5 * shaded_step);
}

TEST(SceneMesh, AnOpenSheetOfNoThicknessIsNotPassedAtOneOrTenMetresASecond) {
  for (double speed : {1.0, 10.0}) {
    Rig rig({{mesh_object("sheet", grid_mesh(64, 0.2))}}, {0.013, 0.007, 0.03}, 0.002);
    double lowest = 1.0;
    for (int k = 0; k < 200; ++k) {
      rig.goal.z() -= speed * 5e-4;
      lowest = std::min(lowest, rig.proxy.update(rig.goal, {0, 0, -speed}).proxy.z());
    }
    EXPECT_GT(lowest, 0.002 - 1e-6) << speed << " m/s";
  }
}

std::filesystem::path temp_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / ("hapticd-mesh-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

const char* const kTetrahedronObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

TEST(SceneMesh, StlObjAndPlyFilesAreRead) {
  const auto obj = load_mesh_file(temp_file("t.obj", kTetrahedronObj), Eigen::Vector3d::Constant(0.01));
  EXPECT_EQ(obj.triangles.size(), 4u);
  EXPECT_NEAR(obj.vertices[1].x() + obj.vertices[2].x() + obj.vertices[3].x(), 0.01, 1e-12);
  const auto stl = load_mesh_file(temp_file("t.stl", R"(solid t
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 0 1 0
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex 1 0 0
  vertex 1 1 0
  vertex 0 1 0
 endloop
endfacet
endsolid t
)"),
                                  Eigen::Vector3d::Ones());
  EXPECT_EQ(stl.triangles.size(), 2u);
  EXPECT_EQ(stl.vertices.size(), 4u) << "shared corners joined";
  const auto ply = load_mesh_file(temp_file("t.ply", R"(ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 2
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
1 1 0
0 1 0
4 0 1 2 3
3 0 2 3
)"),
                                  Eigen::Vector3d::Ones());
  EXPECT_EQ(ply.triangles.size(), 3u) << "a quad becomes two triangles";
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(SceneMesh, EveryKindOfBadMeshIsRefusedWithItsName) {
  const Eigen::Vector3d one = Eigen::Vector3d::Ones();
  EXPECT_NE(error_of([&] { (void)load_mesh_file("/nonexistent/m.stl", one); }).find("/nonexistent/m.stl: no such"),
            std::string::npos);
  EXPECT_NE(
      error_of([&] { (void)load_mesh_file(std::filesystem::temp_directory_path(), one); }).find("not a regular file"),
      std::string::npos);
  const auto junk = temp_file("junk.stl", "this is not a mesh\n\x01\x02");
  EXPECT_NE(error_of([&] { (void)load_mesh_file(junk, one); }).find("junk.stl"), std::string::npos);
  const auto big = temp_file("big.stl", "");
  std::filesystem::resize_file(big, kMaxMeshFileBytes + 1);  // sparse: nothing written
  EXPECT_NE(error_of([&] { (void)load_mesh_file(big, one); }).find("bytes: a mesh file may have at most"),
            std::string::npos);
  std::filesystem::remove(big);
  TriangleMeshData nan = grid_mesh(2, 1.0);
  nan.vertices[3].y() = std::nan("");
  EXPECT_NE(error_of([&] { (void)MeshShape::build(nan, "bad"); }).find("mesh 'bad': vertex 3 is not finite"),
            std::string::npos);
  TriangleMeshData out_of_range = grid_mesh(2, 1.0);
  out_of_range.triangles[1][2] = 99;
  EXPECT_NE(error_of([&] { (void)MeshShape::build(out_of_range, "bad"); }).find("triangle 1 names vertex 99"),
            std::string::npos);
  TriangleMeshData flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  EXPECT_NE(error_of([&] { (void)MeshShape::build(flat, "line"); }).find("no triangle with an area"),
            std::string::npos);
  TriangleMeshData some_flat = grid_mesh(2, 1.0);
  some_flat.triangles.push_back({0, 1, 2});  // colinear: dropped, counted
  some_flat.triangles.push_back({4, 4, 4});
  EXPECT_EQ(MeshShape::build(some_flat, "ok")->dropped_degenerate(), 2u);
}

TEST(SceneMesh, ASceneFileNamesAMeshFileRelativeToItself) {
  temp_file("tet.obj", kTetrahedronObj);
  const auto scene_path =
      temp_file("mesh-scene.yaml", "objects:\n  - {name: tet, shape: mesh, file: tet.obj, scale: 0.02}\n");
  const Scene s = load_scene_file(scene_path);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].shape.mesh->data().triangles.size(), 4u);
  const auto broken = temp_file("broken-scene.yaml", "objects:\n  - name: m\n    shape: mesh\n    file: missing.stl\n");
  const std::string e = error_of([&] { (void)load_scene_file(broken); });
  EXPECT_NE(e.find("broken-scene.yaml:4: objects[0].file:"), std::string::npos) << e;
  EXPECT_NE(e.find("missing.stl: no such mesh file"), std::string::npos) << e;
}

TEST(SceneMesh, UpdateAgainstAMeshAllocatesNothing) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "the sanitizer owns malloc";
  Rig rig({{mesh_object("ball", icosphere_mesh(5, 0.05))}}, {0.0, 0.0, 0.08});
  rig.move({0.0, 0.0, 0.052});
  const std::size_t n = testing::count_allocations([&] {
    for (int k = 0; k < 500; ++k)
      rig.proxy.update(rig.goal + Eigen::Vector3d(4e-5 * k, 0, -1e-5 * k), {0.08, 0, -0.02});
  });
  EXPECT_EQ(n, 0u);
}

}  // namespace
}  // namespace hapticd::scene
