#pragma once
// The scene file (YAML; docs/haptic-scene.md, "The scene file"): named materials and the objects of a haptic
// scene with their shapes, sizes, poses and materials. Every error - a YAML syntax error, an unknown or missing
// key, a size that is not positive, a value that is not finite, a material nobody defined - is a SceneFileError
// whose message names the file, the line and the key ("scene.yaml:12: objects[1].radius: must be positive").
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

#include "hapticd/scene/mesh.hpp"
#include "hapticd/scene/scene.hpp"

namespace hapticd::scene {

class SceneFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// At most this many triangles in all of a scene's meshes.
inline constexpr std::size_t kMaxSceneTriangles = 4'000'000;

// Reads and checks a scene file. Not real-time safe.
[[nodiscard]] Scene load_scene_file(const std::filesystem::path& file);
// The same from text (`name` stands for the file in messages; mesh files are found relative to its folder).
[[nodiscard]] Scene parse_scene(const std::string& text, const std::string& name);

// A scene file's objects and its named materials (for the objects added to it later).
struct SceneDocument {
  Scene scene;
  std::map<std::string, Material> materials;
};
[[nodiscard]] SceneDocument load_scene_document(const std::filesystem::path& file);
[[nodiscard]] SceneDocument parse_scene_document(const std::string& text, const std::string& name);

// A client's edit: one object written as a scene file's (YAML or JSON - JSON is YAML), its material a name from
// `materials` or one in place; or one material so. `name` stands for the text in messages ("the engine's object").
// Files are refused here (a mesh or hull file named by a client is not the server's to open). A mesh the client
// uploaded comes as `uploaded`: the object is then a `mesh` that names it (`upload: NAME`, no file), and its
// triangles are checked and built here (MeshShape::build: a clear error naming the object).
[[nodiscard]] SceneObject parse_scene_object(const std::string& text, const std::string& name,
                                             const std::map<std::string, Material>& materials,
                                             TriangleMeshData* uploaded = nullptr);
[[nodiscard]] Material parse_material(const std::string& text, const std::string& name,
                                      const std::map<std::string, Material>& materials);

}  // namespace hapticd::scene
