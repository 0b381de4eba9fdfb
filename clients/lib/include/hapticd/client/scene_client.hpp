#pragma once
// The session's haptic scene over DDS (docs/haptic-scene.md, "Engines edit the scene"): an engine claims the scene,
// adds objects (JSON, as the scene file writes one), uploads meshes, moves its moving objects at its frame rate,
// changes materials, removes objects, and asks for the objects and for what every device's hand does to them
// (contacts). Client::scene() gives one, made on first use (its three topics: hapticd_scene_request,
// hapticd_scene_mesh_part, hapticd_scene_reply), on the client's participant - the scene's claim is the client's.
//
// Every call but move waits for the server's answer up to its timeout (sent again, with the same id, every 250 ms
// without one; the server applies it once). move is not answered when it goes through; a refused move is, and is
// counted here (refused_moves, last_refusal). Thread-safe: calls may come from any thread, concurrently (not from a
// client's callbacks, which must not wait).
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/client/types.hpp"

namespace hapticd::client {

// One object of the scene (SceneClient::objects).
struct SceneObject {
  std::string name;
  std::string shape;  // plane, sphere, box, capsule, cylinder, mesh (a convex hull: the mesh of its faces)
  std::uint64_t uid = 0;
  bool moving = false;
  std::uint64_t triangles = 0;  // of a mesh
  Pose pose;                    // as added
};

// What one device's hand does to one object (SceneClient::contacts): the force on the object (world frame, N), its
// torque about the object's origin as the device rendered it (N m), at the contact point (m).
struct SceneContact {
  std::string device;
  std::string object_name;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

struct SceneReply {
  bool answered = false;  // false: no answer within the timeout (message says so)
  bool accepted = false;
  std::string message;                 // why it was refused, or what was done
  std::vector<SceneObject> objects;    // objects(): every object
  std::vector<SceneContact> contacts;  // contacts(): every contact
};

class HAPTICD_API SceneClient {
 public:
  // A mesh's part on the wire holds up to this many vertices and as many triangles (add_mesh splits a mesh so).
  static constexpr std::size_t kPartVertices = 1024;
  static constexpr std::size_t kPartTriangles = 1024;

  ~SceneClient();
  SceneClient(const SceneClient&) = delete;
  SceneClient& operator=(const SceneClient&) = delete;

  SceneReply claim(Timeout timeout = kDefaultTimeout);
  SceneReply release(Timeout timeout = kDefaultTimeout);
  // object: JSON, as the scene file writes one - {"name": "wall", "shape": "box", "size": [...], "pose": {...},
  // "material": ..., "moving": true}. At most 4095 bytes (a longer one is refused here).
  SceneReply add(std::string_view object, Timeout timeout = kDefaultTimeout);
  // A mesh: object as for add ({"name": ..., "shape": "mesh", ...} without a file); vertices three coordinates each
  // (m, the object's frame), triangles three indices into them each. Uploaded in parts (each answered), then added;
  // the server checks and builds it (seconds for a million triangles: timeout is for each step).
  SceneReply add_mesh(std::string_view object, std::span<const double> vertices,
                      std::span<const std::uint32_t> triangles, Timeout timeout = kDefaultTimeout);
  SceneReply remove(std::string_view object, Timeout timeout = kDefaultTimeout);
  // material: a name from the scene's materials, or a material in JSON ({"stiffness": 2000, ...}).
  SceneReply set_material(std::string_view object, std::string_view material, Timeout timeout = kDefaultTimeout);
  // A moving object's new pose (world frame), played back by every device between updates. False when it could not
  // be written; a refusal comes later (refused_moves).
  bool move(std::string_view object, const Pose& pose);
  // Every object (the pages of the answer gathered).
  SceneReply objects(Timeout timeout = kDefaultTimeout);
  // Every device's contacts with the objects, as of the devices' latest cycles (an engine asks at its frame rate).
  SceneReply contacts(Timeout timeout = kDefaultTimeout);

  [[nodiscard]] std::uint64_t refused_moves() const;
  [[nodiscard]] std::string last_refusal() const;  // the newest refused move's reason

  struct Impl;
  explicit SceneClient(std::unique_ptr<Impl> impl);

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapticd::client
