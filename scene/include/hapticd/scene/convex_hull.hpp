#pragma once
// The convex hull of a point set (docs/haptic-scene.md, "Convex hulls"), as the triangles of its faces wound
// outwards: the scene meets a hull as a mesh (MeshShape), every edge of which is convex, so each contact is a face,
// an edge or a corner of its own. Not real-time: off the loop, when a scene is loaded or an object created.
// Quickhull (Barber, Dobkin and Huhdanpaa 1996): each point outside a face waits in that face's list; the
// farthest one of a face is added at a time, the faces it sees are replaced by a fan from it to their horizon.
// Points within a tolerance of a face (1e-9 of the set's extent) count as on it: coplanar points add no sliver.
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "hapticd/scene/mesh.hpp"

namespace hapticd::scene {

inline constexpr std::size_t kMaxHullPoints = 1'000'000;

// The hull of `points`. std::invalid_argument naming `name` when there are fewer than 4 points, more than
// kMaxHullPoints, a coordinate that is not finite, or no volume (all points on one plane or line).
[[nodiscard]] TriangleMeshData convex_hull(const std::vector<Eigen::Vector3d>& points, const std::string& name);

}  // namespace hapticd::scene
