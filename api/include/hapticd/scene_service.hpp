#pragma once
// The session's haptic scene (its `scene` section; docs/haptic-scene.md, "The session's scene"): a plugin of its
// own kind that holds the one scene the session's devices render and the doors edit. The server loads it only for
// a session with the section - so a session without a scene never maps the scene's libraries (its meshes'
// acceleration structure, its file loader) - configures it before any device's chain and hands it to every chain
// plugin in PluginContext::scene and to the doors.
//
// Every method is called off the loop, from any thread (the doors' and the server's); an implementation
// serialises its edits. A refused edit throws std::invalid_argument with a message that names the object and the
// reason, and changes nothing. A loop reads the scene through scene::SharedScene's readers (shared()), never
// through this interface.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd {
namespace scene {
class SharedScene;
}  // namespace scene

// One object of the scene as the doors see it.
struct SceneObjectSummary {
  std::string name;
  std::string shape;  // plane, sphere, box, capsule, cylinder, mesh (a convex hull is met as the mesh of its faces)
  std::uint64_t uid = 0;
  bool moving = false;
  std::size_t triangles = 0;  // of a mesh
  Pose pose;                  // as added (a moving object's later poses are the devices' to play back)
};

// What one device's hand does to one object now: the force on the object (world frame, N) and its torque about
// the object's origin (N m), at the contact point. An engine's physics applies it to its copy of the object.
struct SceneContact {
  std::string device;
  std::string object;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

// The scene as a viewer draws it (the live view, docs/live-view.md): each object's shape, its size and where it is
// now, and each device's proxy.
struct SceneObjectDrawing {
  std::string name;
  std::string shape;  // as in SceneObjectSummary
  bool moving = false;
  Pose pose;  // now: a moving object's newest pose
  // box: the edge lengths; sphere: the radius; capsule, cylinder: the radius and the length (along the object's z)
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  // mesh: up to drawing()'s max_triangles of its triangles (every k-th of a larger one), three corners each, in
  // the object's frame; triangles: how many it has
  std::vector<Eigen::Vector3f> corners;
  std::size_t triangles = 0;
};
struct SceneProxyDrawing {
  std::string device;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double radius = 0.0;
  bool touching = false;
};
struct SceneDrawing {
  std::vector<SceneObjectDrawing> objects;
  std::vector<SceneProxyDrawing> proxies;
};

class HAPTICD_API SceneService {
 public:
  virtual ~SceneService();

  // Reads the scene's objects at the start (the plugin's parameters: a scene file). Throws ParameterError for a
  // mistake in them (the server names the session file's key and line).
  virtual void configure(const Parameters& parameters, const PluginContext& context) = 0;

  // The scene the devices render: a haptic_scene model takes a reader of it (scene/shared_scene.hpp; the scene
  // library is the plugin's and the models', not the server's).
  [[nodiscard]] virtual scene::SharedScene& shared() noexcept = 0;

  // Adds one object written as the scene file writes one (YAML or JSON: name, shape, sizes, pose, material - a
  // name from the scene file's materials or one in place - and `moving` for an object an engine moves); a mesh or
  // hull file is refused here (a client's file is not the server's to read). Returns the object's uid.
  virtual std::uint64_t add(std::string_view object) = 0;
  // Adds a mesh an engine uploaded: `object` as for add(), a `mesh` with `upload: NAME` in place of a file;
  // `vertices` three coordinates each (metres, the object's frame), `triangles` three indices into them each. The
  // triangles are checked (finite, indices in range, the caps; degenerate ones dropped) and built here, on the
  // caller's thread: an error names the object.
  virtual std::uint64_t add_mesh(std::string_view object, std::vector<double> vertices,
                                 std::vector<std::uint32_t> triangles) = 0;
  virtual void remove(std::string_view name) = 0;
  // The object's material: a name from the scene file's materials or a material in place (YAML or JSON).
  virtual void set_material(std::string_view name, std::string_view material) = 0;
  // A moving object's new pose, played back by every device (an update is never felt as a step).
  virtual void move(std::string_view name, const Pose& pose) = 0;
  [[nodiscard]] virtual std::vector<SceneObjectSummary> objects() const = 0;
  // Every device's contacts with the objects as of their latest cycles (an engine asks at its own rate).
  [[nodiscard]] virtual std::vector<SceneContact> contacts() = 0;
  // The scene as a viewer draws it now, each mesh with at most max_triangles of its triangles.
  [[nodiscard]] virtual SceneDrawing drawing(std::size_t max_triangles) = 0;
};

}  // namespace hapticd
