#pragma once
// One triangle's geometry for the proxy (docs/haptic-scene.md, "Meshes"): the point of a triangle closest to a
// point, with its barycentric coordinates (for force shading: the vertex normals interpolated there). A triangle
// is convex, so the plane through that closest point, normal to the direction from it to the point, separates
// the point from the whole triangle - the proxy's sweep advances against meshes triangle by triangle.
// Real-time safe.
#include <Eigen/Core>

namespace hapticd::scene {

struct TrianglePoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d barycentric = Eigen::Vector3d(1.0, 0.0, 0.0);  // weights of a, b, c
};

// Ericson's region test (Real-Time Collision Detection, 5.1.5): exact, no division by a degenerate triangle's
// zero area (a degenerate triangle gives a point of its edges).
[[nodiscard]] TrianglePoint closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                                const Eigen::Vector3d& b, const Eigen::Vector3d& c) noexcept;

}  // namespace hapticd::scene
