// Convex hulls (scene/convex_hull.hpp): the hull of a cube's corners among inner and coplanar points is the cube's
// 12 triangles; of points on and in a sphere, a closed surface wound outwards with every point inside it and every
// point of the sphere a vertex; degenerate sets are refused by name; the scene file takes a hull of listed points
// or of a mesh file's vertices, and the scene meets it as a mesh whose faces face outwards.
#include "hapticd/scene/convex_hull.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "hapticd/scene/scene_file.hpp"
#include "support/test_paths.hpp"

namespace hapticd::scene {
namespace {

using Vec = Eigen::Vector3d;

// Volume by the divergence theorem (positive: wound outwards), and whether every directed edge has its twin.
double volume(const TriangleMeshData& m) {
  double v = 0.0;
  for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
  return v;
}
bool closed(const TriangleMeshData& m) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k)
      if (!edges.insert({t[static_cast<std::size_t>(k)], t[(k + 1) % 3]}).second) return false;  // an edge twice
  for (const auto& [a, b] : edges)
    if (edges.count({b, a}) == 0) return false;
  return true;
}
// The largest height of any point above any face's plane (<= 0 up to rounding: all inside).
double worst_outside(const TriangleMeshData& m, const std::vector<Vec>& points) {
  double worst = -1e300;
  for (const auto& t : m.triangles) {
    const Vec& a = m.vertices[t[0]];
    const Vec n = (m.vertices[t[1]] - a).cross(m.vertices[t[2]] - a).normalized();
    for (const Vec& p : points) worst = std::max(worst, n.dot(p - a));
  }
  return worst;
}

TEST(ConvexHull, ACubesCornersAmongInnerAndCoplanarPointsGiveTheCube) {
  std::vector<Vec> points;
  for (int i = 0; i < 8; ++i) points.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 500; ++i) points.emplace_back(u(random), u(random), u(random));          // inside
  for (int i = 0; i < 200; ++i) points.emplace_back(u(random), u(random), i % 2 ? 1.0 : 0.0);  // on faces
  for (int i = 0; i < 100; ++i) points.emplace_back(u(random), 0.0, 1.0);                      // on an edge
  const TriangleMeshData hull = convex_hull(points, "cube");
  EXPECT_EQ(hull.vertices.size(), 8u);
  EXPECT_EQ(hull.triangles.size(), 12u);
  EXPECT_NEAR(volume(hull), 1.0, 1e-12);
  EXPECT_TRUE(closed(hull));
  EXPECT_LE(worst_outside(hull, points), 1e-12);
}

TEST(ConvexHull, PointsOnAndInASphereGiveAClosedOutwardSurfaceThroughEverySurfacePoint) {
  std::mt19937 random(7);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec> points;
  for (int i = 0; i < 3000; ++i) points.push_back(Vec(g(random), g(random), g(random)).normalized() * 0.05);
  for (int i = 0; i < 3000; ++i)
    // Inside the sphere's polytope: its faces sag at most 0.3 % of the radius below the sphere between 3000 points.
    points.push_back(Vec(g(random), g(random), g(random)).normalized() * 0.05 * 0.95 * std::cbrt(u(random)));
  const TriangleMeshData hull = convex_hull(points, "ball");
  EXPECT_EQ(hull.vertices.size(), 3000u);  // every point of the sphere is extreme, none of the inner ones
  EXPECT_TRUE(closed(hull));
  // A closed surface of genus 0: V - E + F = 2, with E = 3F/2.
  EXPECT_EQ(static_cast<long>(hull.vertices.size()) - static_cast<long>(hull.triangles.size()) / 2, 2);
  EXPECT_NEAR(volume(hull), 4.0 / 3.0 * M_PI * std::pow(0.05, 3), 0.02 * 4.0 / 3.0 * M_PI * std::pow(0.05, 3));
  EXPECT_LE(worst_outside(hull, points), 1e-12);
}

TEST(ConvexHull, EveryCloudOfASweepGivesAClosedOutwardHullWithEveryPointInside) {
  // 300 clouds: random sizes (4 to 600 points), boxes of any proportion, and lattices (many points on one plane, on
  // one line, on the hull's edges) rotated and shifted at random - the degenerate sets a tolerance must survive.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int cloud = 0; cloud < 300; ++cloud) {
    SCOPED_TRACE(cloud);
    std::vector<Vec> points;
    const Eigen::Matrix3d turn =
        Eigen::Quaterniond(Eigen::Vector4d(u(random), u(random), u(random), u(random)).normalized()).toRotationMatrix();
    const Vec shift(u(random), u(random), u(random));
    if (cloud % 3 == 0) {  // a lattice
      const int n = 2 + cloud % 5;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          for (int k = 0; k < n; ++k) points.push_back(turn * Vec(i, j, k) * 0.01 + shift);
    } else {
      const Vec extent(std::abs(u(random)) + 1e-3, std::abs(u(random)) + 1e-3, std::abs(u(random)) + 1e-3);
      const int n = 4 + static_cast<int>(std::abs(u(random)) * 596);
      for (int i = 0; i < n; ++i)
        points.push_back(turn * Vec(u(random), u(random), u(random)).cwiseProduct(extent) + shift);
    }
    const TriangleMeshData hull = convex_hull(points, "cloud");
    EXPECT_TRUE(closed(hull));
    EXPECT_GT(volume(hull), 0.0);
    EXPECT_LE(worst_outside(hull, points), 1e-9 * 4.0);
  }
}

TEST(ConvexHull, SetsWithoutAVolumeAreRefusedByName) {
  const auto error_of = [](const std::vector<Vec>& points) {
    try {
      (void)convex_hull(points, "thing");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).find("thing: a convex hull needs at least 4 points"),
            std::string::npos);
  std::vector<Vec> flat;
  for (int i = 0; i < 20; ++i) flat.emplace_back(i % 5, i / 5, 0.0);
  EXPECT_NE(error_of(flat).find("thing: the points have no volume"), std::string::npos);
  std::vector<Vec> line;
  for (int i = 0; i < 20; ++i) line.emplace_back(i, 2 * i, 3 * i);
  EXPECT_NE(error_of(line).find("no volume"), std::string::npos);
  EXPECT_NE(
      error_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, NAN}}).find("point 3 has a coordinate that is not finite"),
      std::string::npos);
}

TEST(ConvexHull, TheSceneFileTakesAHullOfPointsOrOfAMeshFilesVertices) {
  const Scene s = parse_scene(R"(objects:
  - name: block
    shape: convex_hull
    points: [[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0], [0, 0, 0.1], [0.1, 0, 0.1], [0, 0.1, 0.1], [0.1, 0.1, 0.1], [0.05, 0.05, 0.05]]
    position: [0, 0, -0.2]
  - {name: pebble, shape: convex_hull, file: )" +
                                  hapticd::test::source_dir() +
                                  R"(/config/haptic-scenes/pebble.obj, scale: 0.5}
)",
                              "s.yaml");
  ASSERT_EQ(s.objects.size(), 2u);
  const MeshShape& block = *s.objects[0].shape.mesh;
  EXPECT_EQ(block.data().triangles.size(), 12u);
  // Outwards: the face nearest a point above the top is the top, its normal up, 0.05 m away.
  MeshShape::Near near{};
  ASSERT_TRUE(block.nearest(Vec(0.05, 0.05, 0.15), 1.0, near));
  EXPECT_NEAR((near.closest.point - Vec(0.05, 0.05, 0.15)).norm(), 0.05, 1e-12);
  EXPECT_NEAR(block.face_normal(near.triangle).z(), 1.0, 1e-12);
  EXPECT_GT(s.objects[1].shape.mesh->data().triangles.size(), 20u);
  EXPECT_TRUE(closed(s.objects[1].shape.mesh->data()));
  const auto error_of = [](const std::string& text) {
    try {
      (void)parse_scene(text, "s.yaml");
    } catch (const SceneFileError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of("objects:\n  - {name: h, shape: convex_hull}\n").find("s.yaml:2: objects[0].points"),
            std::string::npos);
  EXPECT_NE(error_of("objects:\n  - {name: h, shape: convex_hull, points: [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}\n")
                .find("h: a convex hull needs at least 4 points"),
            std::string::npos);
  EXPECT_NE(error_of("objects:\n  - {name: h, shape: convex_hull, radius: 1, points: []}\n").find("has no radius"),
            std::string::npos);
}

}  // namespace
}  // namespace hapticd::scene
