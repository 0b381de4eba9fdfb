#pragma once
// A triangle mesh of the haptic scene and its acceleration structure (docs/haptic-scene.md, "Meshes"). Built off
// the loop (MeshShape::build: the checks, the vertex normals for force shading, Embree's BVH) and immutable after:
// the loop only asks it for the triangles near a point, each with its exact closest point (double precision; the
// BVH, in single precision, only culls - its radius is widened to stay conservative). Embree was chosen by
// measurement against Bullet and FCL (bench/scene_mesh_index.cpp, docs/haptic-scene.md).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hapticd/scene/triangle.hpp"

struct RTCPointQueryFunctionArguments;

namespace hapticd::scene {

struct TriangleMeshData {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// Limits a mesh is checked against (MeshShape::build refuses a mesh beyond them, naming it).
inline constexpr std::size_t kMaxMeshTriangles = 4'000'000;
inline constexpr std::size_t kMaxMeshVertices = 4'000'000;

class MeshShape {
 public:
  // Not real-time safe. Checks the mesh (finite coordinates, indices in range, at least one triangle, the caps;
  // degenerate triangles - zero area - are dropped and counted), computes the vertex normals (angle-weighted) and
  // builds the BVH. std::invalid_argument naming `name` and what is wrong.
  static std::shared_ptr<const MeshShape> build(TriangleMeshData data, const std::string& name);
  ~MeshShape();
  MeshShape(const MeshShape&) = delete;
  MeshShape& operator=(const MeshShape&) = delete;

  struct Near {
    std::uint32_t triangle;
    TrianglePoint closest;  // the triangle's point closest to the query point, and its barycentric coordinates
  };
  using NearFunction = void (*)(void* context, const Near& near);
  // Real-time safe: calls `f` for every triangle whose closest point lies within `radius` of `p` (mesh frame),
  // each once.
  void for_each_near(const Eigen::Vector3d& p, double radius, NearFunction f, void* context) const noexcept;
  // Real-time safe: as for_each_near, leaving out triangles wholly behind `p` along `u` (no point of theirs ahead:
  // a sphere moving along `u` from `p` cannot approach them); a zero `u` leaves none out.
  void for_each_ahead(const Eigen::Vector3d& p, double radius, const Eigen::Vector3d& u, NearFunction f,
                      void* context) const noexcept;
  // Real-time safe: the triangle nearest `p` within `max_distance` (the query shrinks as it finds nearer ones);
  // false when there is none that near.
  bool nearest(const Eigen::Vector3d& p, double max_distance, Near& out) const noexcept;
  // The vertex normals interpolated at a triangle's barycentric coordinates (unit; force shading).
  [[nodiscard]] Eigen::Vector3d shaded_normal(std::uint32_t triangle,
                                              const Eigen::Vector3d& barycentric) const noexcept;
  // Whether a closest point at these barycentric coordinates is a contact of its own: inside the face, or on an
  // edge or corner where the surface bends away (a convex edge, or the mesh's border). On an edge to a coplanar or
  // concave neighbour it is not - the neighbour's face holds the proxy there, and the sphere's rounded normal at
  // the edge would tilt the contact for nothing.
  [[nodiscard]] bool own_contact(std::uint32_t triangle, const Eigen::Vector3d& barycentric) const noexcept;
  // The triangle's own (face) normal, by its winding.
  [[nodiscard]] Eigen::Vector3d face_normal(std::uint32_t triangle) const noexcept;

  [[nodiscard]] const TriangleMeshData& data() const noexcept { return data_; }
  [[nodiscard]] double bounding_radius() const noexcept { return bounding_radius_; }
  [[nodiscard]] std::size_t dropped_degenerate() const noexcept { return dropped_; }

 private:
  MeshShape() = default;
  [[nodiscard]] float culling_radius(const Eigen::Vector3d& p, double radius) const noexcept;
  void query(const Eigen::Vector3d& p, double radius, bool (*callback)(RTCPointQueryFunctionArguments*),
             void* context) const noexcept;
  // Whether every point of `triangle` lies farther than `radius` from `p`, by its bounding ball: the structure's
  // leaves hand on many triangles beyond a query's radius (nine in ten on a dense mesh), and this test is a tenth
  // of the exact closest point's cost.
  [[nodiscard]] bool beyond(std::uint32_t triangle, const Eigen::Vector3d& p, double radius) const noexcept {
    const Ball& b = balls_[triangle];
    const double reach = radius + b.radius;
    return (p - b.centre).squaredNorm() > reach * reach;
  }
  struct Ball {
    Eigen::Vector3d centre;  // the corners' mean
    double radius;           // to the farthest corner
  };
  TriangleMeshData data_;
  std::vector<Ball> balls_;                    // per triangle
  std::vector<Eigen::Vector3d> normals_;       // per vertex
  std::vector<Eigen::Vector3d> face_normals_;  // per triangle
  std::vector<std::array<bool, 3>> convex_;    // per triangle, per edge (a-b, b-c, c-a): bends away, or a border
  double bounding_radius_ = 0.0;
  std::size_t dropped_ = 0;
  struct Index;
  std::unique_ptr<Index> index_;
};

}  // namespace hapticd::scene
