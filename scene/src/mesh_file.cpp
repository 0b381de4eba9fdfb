#include "hapticd/scene/mesh_file.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <map>
#include <stdexcept>

namespace hapticd::scene {
namespace {

void add_node(const aiScene* s, const aiNode* node, const aiMatrix4x4& parent, TriangleMeshData& out) {
  const aiMatrix4x4 transform = parent * node->mTransformation;
  for (unsigned m = 0; m < node->mNumMeshes; ++m) {
    const aiMesh* mesh = s->mMeshes[node->mMeshes[m]];
    if ((mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
    const auto base = static_cast<std::uint32_t>(out.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D p = transform * mesh->mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      out.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) add_node(s, node->mChildren[c], transform, out);
}

}  // namespace

TriangleMeshData load_mesh_file(const std::filesystem::path& file, const Eigen::Vector3d& scale) {
  auto fail = [&](const std::string& what) { throw std::invalid_argument(file.string() + ": " + what); };
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (ec || !std::filesystem::exists(status)) fail("no such mesh file");
  if (!std::filesystem::is_regular_file(status)) fail("not a regular file");
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (ec) fail("cannot read its size");
  if (bytes > kMaxMeshFileBytes)
    fail(std::to_string(bytes) + " bytes: a mesh file may have at most " + std::to_string(kMaxMeshFileBytes));
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* s = importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                          aiProcess_SortByPType | aiProcess_FindInvalidData);
  if (s == nullptr || s->mRootNode == nullptr || (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0)
    fail(std::string("not a mesh the loader reads (STL, OBJ, PLY, glTF): ") + importer.GetErrorString());
  TriangleMeshData out;
  add_node(s, s->mRootNode, aiMatrix4x4(), out);
  if (out.triangles.empty()) fail("no triangles in it");
  for (auto& v : out.vertices) v = v.cwiseProduct(scale);
  return out;
}

TriangleMeshData icosphere_mesh(int subdivisions, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMeshData m;
  for (const Eigen::Vector3d& v :
       {Eigen::Vector3d(-1, t, 0), Eigen::Vector3d(1, t, 0), Eigen::Vector3d(-1, -t, 0), Eigen::Vector3d(1, -t, 0),
        Eigen::Vector3d(0, -1, t), Eigen::Vector3d(0, 1, t), Eigen::Vector3d(0, -1, -t), Eigen::Vector3d(0, 1, -t),
        Eigen::Vector3d(t, 0, -1), Eigen::Vector3d(t, 0, 1), Eigen::Vector3d(-t, 0, -1), Eigen::Vector3d(-t, 0, 1)})
    m.vertices.push_back(v.normalized());
  m.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
    auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, fresh] = middle.try_emplace(key, static_cast<std::uint32_t>(m.vertices.size()));
      if (fresh) m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    next.reserve(m.triangles.size() * 4);
    for (const auto& tri : m.triangles) {
      const std::uint32_t a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]), c = mid(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    m.triangles = std::move(next);
  }
  for (auto& v : m.vertices) v *= radius;
  return m;
}

TriangleMeshData grid_mesh(int n, double size) {
  TriangleMeshData m;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      m.vertices.emplace_back(size * (static_cast<double>(i) / n - 0.5), size * (static_cast<double>(j) / n - 0.5),
                              0.0);
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>(i * (n + 1) + j); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

}  // namespace hapticd::scene
