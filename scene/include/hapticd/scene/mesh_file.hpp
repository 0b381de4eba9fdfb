#pragma once
// Reading a triangle mesh file for the haptic scene (docs/haptic-scene.md, "Meshes"): STL (binary and ASCII), OBJ,
// PLY and glTF 2.0 through Assimp, off the loop. Only a regular file no larger than the limit is read; every
// polygon becomes triangles, points and lines are left out, every part of the file's node tree is placed where
// the tree puts it, then scaled. std::invalid_argument names the file and what is wrong.
#include <filesystem>

#include "hapticd/scene/mesh.hpp"

namespace hapticd::scene {

// A 1-million-triangle binary STL is 50 MB.
inline constexpr std::uintmax_t kMaxMeshFileBytes = 256u * 1024u * 1024u;

[[nodiscard]] TriangleMeshData load_mesh_file(const std::filesystem::path& file, const Eigen::Vector3d& scale);

// Generated meshes (tests, benchmarks, the shipped scene's mesh): an icosphere of `subdivisions` levels (20 x 4^n
// triangles, outward winding) and a flat square grid of 2 x n x n triangles in the plane z = 0, facing +z.
[[nodiscard]] TriangleMeshData icosphere_mesh(int subdivisions, double radius);
[[nodiscard]] TriangleMeshData grid_mesh(int n, double size);

}  // namespace hapticd::scene
