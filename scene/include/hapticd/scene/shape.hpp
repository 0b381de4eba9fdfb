#pragma once
// The analytic shapes of the haptic scene, each in its own frame (docs/haptic-scene.md, "Shapes"):
//   plane     the half-space z <= 0 (the surface z = 0, its outward normal +z)
//   sphere    radius r about the origin
//   box       half extents (x, y, z) about the origin
//   capsule   radius r about the segment from (0, 0, -h) to (0, 0, h)
//   cylinder  radius r about the z axis, between z = -h and z = h (flat caps)
//   mesh      triangles (mesh.hpp): not convex as a whole, but each triangle is - the proxy meets a mesh triangle
//             by triangle through its structure, never through closest_point()
// All are convex: the plane through a point's closest surface point, normal to the outward normal there,
// separates the point from the whole shape - what the proxy's sweep relies on (proxy.hpp).
// Real-time safe: no allocation.
#include <Eigen/Core>
#include <memory>

namespace hapticd::scene {

enum class ShapeKind { plane, sphere, box, capsule, cylinder, mesh };

class MeshShape;

struct Shape {
  ShapeKind kind = ShapeKind::sphere;
  double radius = 0.0;                                     // sphere, capsule, cylinder [m]
  double half_length = 0.0;                                // capsule, cylinder: half the axis length [m]
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // box [m]
  std::shared_ptr<const MeshShape> mesh;                   // mesh: its triangles and their structure
};

// A point's relation to a shape's surface, in the shape's frame.
struct SurfacePoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // the closest point of the surface
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // the outward unit normal there
  double distance = 0.0;                              // signed: negative inside
};

// The surface point closest to `p` (shape frame). Exact for every analytic kind; inside, the nearest face's
// point. A mesh answers its nearest triangle's point within 1 m (unsigned: a mesh has no inside), else far away.
[[nodiscard]] SurfacePoint closest_point(const Shape& shape, const Eigen::Vector3d& p) noexcept;

// The radius of a sphere about the shape's origin that holds it (infinite for the plane).
[[nodiscard]] double bounding_radius(const Shape& shape) noexcept;

// The name of a kind as the scene file writes it.
[[nodiscard]] const char* kind_name(ShapeKind kind) noexcept;

}  // namespace hapticd::scene
