#pragma once
// The session's haptic scene as the live view shows it (docs/live-view.md, channel /haptic_scene/scene): the
// scene's objects - shapes at their sizes, meshes as triangle lists (at most kMaxTriangles a mesh: every k-th
// triangle of a larger one) - and each device's proxy (a sphere of its radius, orange while it touches something).
// Drawn on the live view's thread from SceneService::drawing(): the still objects when they change (and every 2 s,
// for a viewer that came late), the moving objects and the proxies at every update.
#include <cstdint>
#include <string>

#include "hapticd/scene_service.hpp"

namespace hapticd::server::live_view {

class HapticSceneView {
 public:
  static constexpr std::size_t kMaxTriangles = 2000;
  static constexpr std::int64_t kStillEveryNs = 2'000'000'000;

  explicit HapticSceneView(SceneService& scene) : scene_(scene) {}

  // The live view's thread: the scene update to send now into `out`.
  void scene_update(std::uint64_t time_ns, std::int64_t now_ns, std::string& out);

 private:
  SceneService& scene_;
  std::string still_signature_;  // the still objects last drawn (names and poses)
  std::int64_t still_sent_ns_ = 0;
  bool sent_ = false;
};

// The entities of a drawing (for tests): "haptic_scene/still" (with_still), "haptic_scene/moving" and
// "haptic_scene/proxies".
void append_scene_entities(std::string& out, std::uint64_t time_ns, const SceneDrawing& d, bool with_still);

}  // namespace hapticd::server::live_view
