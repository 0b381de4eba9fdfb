// The scene's analytic shapes (scene/shape.hpp): for a dense grid of points around each shape, the closest
// point lies on the surface, its distance is the point's, the normal is the distance's gradient (finite
// differences), and no surface point is nearer (a fine sampling of the surface).
#include "hapticd/scene/shape.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace hapticd::scene {
namespace {

Shape sphere(double r) { return {ShapeKind::sphere, r, 0.0, {}, nullptr}; }
Shape box(double x, double y, double z) { return {ShapeKind::box, 0.0, 0.0, {x, y, z}, nullptr}; }
Shape capsule(double r, double h) { return {ShapeKind::capsule, r, h, {}, nullptr}; }
Shape cylinder(double r, double h) { return {ShapeKind::cylinder, r, h, {}, nullptr}; }

// Points on the surface of a shape, densely (for the brute-force nearest point).
std::vector<Eigen::Vector3d> surface_samples(const Shape& s) {
  std::vector<Eigen::Vector3d> out;
  const int n = 60;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
      const double theta = 2.0 * std::numbers::pi * u, phi = std::numbers::pi * v;
      switch (s.kind) {
        case ShapeKind::sphere:
          out.emplace_back(s.radius * Eigen::Vector3d(std::sin(phi) * std::cos(theta), std::sin(phi) * std::sin(theta),
                                                      std::cos(phi)));
          break;
        case ShapeKind::box:
          for (int axis = 0; axis < 3; ++axis)
            for (double side : {-1.0, 1.0}) {
              Eigen::Vector3d p;
              p[axis] = side * s.half_extents[axis];
              p[(axis + 1) % 3] = (2 * u - 1) * s.half_extents[(axis + 1) % 3];
              p[(axis + 2) % 3] = (2 * v - 1) * s.half_extents[(axis + 2) % 3];
              out.push_back(p);
            }
          break;
        case ShapeKind::capsule: {
          out.emplace_back(s.radius * std::cos(theta), s.radius * std::sin(theta), (2 * v - 1) * s.half_length);
          for (double side : {-1.0, 1.0})
            out.emplace_back(s.radius * std::sin(phi / 2) * std::cos(theta),
                             s.radius * std::sin(phi / 2) * std::sin(theta),
                             side * (s.half_length + s.radius * std::cos(phi / 2)));
          break;
        }
        case ShapeKind::cylinder:
          out.emplace_back(s.radius * std::cos(theta), s.radius * std::sin(theta), (2 * v - 1) * s.half_length);
          for (double side : {-1.0, 1.0})
            out.emplace_back(v * s.radius * std::cos(theta), v * s.radius * std::sin(theta), side * s.half_length);
          break;
        case ShapeKind::plane:
        case ShapeKind::mesh:
          break;
      }
    }
  }
  return out;
}

double distance_of(const Shape& s, const Eigen::Vector3d& p) { return closest_point(s, p).distance; }

TEST(SceneShapes, TheClosestPointIsOnTheSurfaceAtTheDistanceWithTheGradientAsNormalForADenseGrid) {
  for (const Shape& s : {sphere(0.03), box(0.04, 0.02, 0.01), capsule(0.015, 0.03), cylinder(0.02, 0.025)}) {
    const std::vector<Eigen::Vector3d> samples = surface_samples(s);
    int checked = 0;
    for (double x = -0.06; x <= 0.06; x += 0.0075)
      for (double y = -0.06; y <= 0.06; y += 0.0075)
        for (double z = -0.06; z <= 0.06; z += 0.0075) {
          const Eigen::Vector3d p(x + 1e-4, y + 2e-4, z + 3e-4);  // off the symmetry planes
          const SurfacePoint c = closest_point(s, p);
          ASSERT_NEAR(std::abs(c.distance), (p - c.point).norm(), 1e-12) << kind_name(s.kind) << " " << p.transpose();
          ASSERT_NEAR(distance_of(s, c.point), 0.0, 1e-12) << kind_name(s.kind);
          ASSERT_NEAR(c.normal.norm(), 1.0, 1e-12);
          // The gradient of the signed distance, where it is smooth (away from the medial surfaces inside).
          const double h = 1e-7;
          Eigen::Vector3d g;
          for (int a = 0; a < 3; ++a) {
            Eigen::Vector3d e = Eigen::Vector3d::Zero();
            e[a] = h;
            g[a] = (distance_of(s, p + e) - distance_of(s, p - e)) / (2 * h);
          }
          if (c.distance > 0.0) {
            ASSERT_LT((g - c.normal).norm(), 1e-5) << kind_name(s.kind) << " at " << p.transpose();
            double nearest = 1e9;
            for (const auto& q : samples) nearest = std::min(nearest, (p - q).norm());
            ASSERT_LE(c.distance, nearest + 1e-12) << kind_name(s.kind) << " at " << p.transpose();
            ASSERT_LT(nearest - c.distance, 0.002) << kind_name(s.kind) << " at " << p.transpose();
          }
          ++checked;
        }
    EXPECT_GT(checked, 4000);
  }
}

TEST(SceneShapes, ThePlaneIsTheHalfSpaceBelowZ) {
  const Shape plane{ShapeKind::plane, 0, 0, {}, nullptr};
  const SurfacePoint c = closest_point(plane, {0.1, -0.2, 0.03});
  EXPECT_NEAR(c.distance, 0.03, 1e-15);
  EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(0.1, -0.2, 0.0)));
  EXPECT_TRUE(c.normal.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_LT(closest_point(plane, {0, 0, -0.01}).distance, 0.0);
}

}  // namespace
}  // namespace hapticd::scene
