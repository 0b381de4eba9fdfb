#pragma once
// The haptic scene: named objects, each a shape with a material at a pose in the session's world frame
// (docs/haptic-scene.md). Built off the loop (scene_file.hpp, or by code) and read by the proxy on the loop; the
// loop never changes it. Real-time safe to query: no allocation.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "hapticd/scene/material.hpp"
#include "hapticd/scene/shape.hpp"

namespace hapticd::scene {

struct SceneObject {
  std::string name;
  Shape shape;
  Material material;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // world <- object
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      // of a moving object (world): its surface's damping is
                                                           // on the hand's speed relative to it
  // A shared scene's (shared_scene.hpp): the object's id, unique for the scene's life (0: none), its slot (its
  // pose track), and whether an engine moves it (its pose is played back every cycle).
  std::uint64_t uid = 0;
  std::uint32_t slot = 0;
  bool moving = false;
};

// The object's surface point closest to a world point, in the world frame.
[[nodiscard]] inline SurfacePoint closest_in_world(const SceneObject& object,
                                                   const Eigen::Vector3d& world_point) noexcept {
  const Eigen::Vector3d local = object.pose.inverse(Eigen::Isometry) * world_point;
  SurfacePoint s = closest_point(object.shape, local);
  s.point = object.pose * s.point;
  s.normal = object.pose.linear() * s.normal;
  return s;
}

// At most this many objects in a scene (a scene is for what a hand touches, not a level of a game): a scene file's,
// a shared scene's.
inline constexpr std::size_t kMaxSceneObjects = 1024;

struct Scene {
  std::vector<SceneObject> objects;
};

}  // namespace hapticd::scene
