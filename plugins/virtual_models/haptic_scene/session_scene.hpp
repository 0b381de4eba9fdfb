#pragma once
// The session's haptic scene (the session file's `scene` section; docs/haptic-scene.md, "The session's scene"): the
// SceneService the server loads for a session with the section. It holds one scene::SharedScene - read, checked and
// built from its scene file here, at configure, off the loop - which the session's haptic_scene models render
// (each takes a reader) and the doors edit by value (an object or a material written as the scene file writes it,
// parsed and built on the caller's thread, never the loop's).
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "hapticd/scene/material.hpp"
#include "hapticd/scene/shared_scene.hpp"
#include "hapticd/scene_service.hpp"

namespace hapticd::models {

class SessionScene final : public SceneService {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  [[nodiscard]] scene::SharedScene& shared() noexcept override { return *scene_; }

  std::uint64_t add(std::string_view object) override;
  std::uint64_t add_mesh(std::string_view object, std::vector<double> vertices,
                         std::vector<std::uint32_t> triangles) override;
  void remove(std::string_view name) override;
  void set_material(std::string_view name, std::string_view material) override;
  void move(std::string_view name, const Pose& pose) override;
  [[nodiscard]] std::vector<SceneObjectSummary> objects() const override;
  [[nodiscard]] std::vector<SceneContact> contacts() override;
  [[nodiscard]] SceneDrawing drawing(std::size_t max_triangles) override;

 private:
  std::uint64_t add_object(scene::SceneObject object);
  std::unique_ptr<scene::SharedScene> scene_ = std::make_unique<scene::SharedScene>();
  std::map<std::string, scene::Material> materials_;  // the scene file's, for the objects added later
  std::size_t triangles_ = 0;                         // in all of the scene's meshes, at most kMaxSceneTriangles
  mutable std::mutex mutex_;                          // the edits' bookkeeping (the scene serialises its own)
};

}  // namespace hapticd::models
