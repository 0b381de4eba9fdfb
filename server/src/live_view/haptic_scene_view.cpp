#include "live_view/haptic_scene_view.hpp"

#include <fmt/format.h>

#include "hapticd/json_text.hpp"
#include "live_view/scene_json.hpp"

namespace hapticd::server::live_view {

namespace {

using json_text::append_number;
using json_text::append_time;
using scene_json::append_colour;
using scene_json::append_pose;
using scene_json::append_sized;
using scene_json::Rgba;

constexpr std::size_t kMaxMovingTriangles = 200;  // a moving mesh goes out at every update: fewer of its triangles
constexpr Rgba kStill{0.55, 0.6, 0.7, 0.8}, kMoving{0.9, 0.75, 0.3, 0.9}, kProxy{0.3, 0.6, 1.0, 0.9},
    kTouching{1.0, 0.55, 0.1, 1.0};

// The entity "haptic_scene/<which>" with the objects `take` selects.
template <class Take>
void append_objects(std::string& out, bool first, std::uint64_t time_ns, const char* which, const SceneDrawing& d,
                    Take&& take, const Rgba& c, std::size_t max_triangles) {
  std::string cubes, spheres, cylinders, triangles;
  for (const SceneObjectDrawing& o : d.objects) {
    if (!take(o)) continue;
    const Eigen::Vector3d& s = o.size;
    if (o.shape == "box") {
      append_sized(cubes, cubes.empty(), o.pose, s, c);
    } else if (o.shape == "sphere") {
      append_sized(spheres, spheres.empty(), o.pose, Eigen::Vector3d::Constant(2.0 * s.x()), c);
    } else if (o.shape == "cylinder" || o.shape == "capsule") {
      append_sized(cylinders, cylinders.empty(), o.pose, Eigen::Vector3d(2 * s.x(), 2 * s.x(), s.y()), c, true);
      if (o.shape == "capsule") {
        const Eigen::Vector3d axis = o.pose.orientation * Eigen::Vector3d::UnitZ();
        for (const double end : {-0.5, 0.5})
          append_sized(spheres, spheres.empty(), Pose{o.pose.position + end * s.y() * axis, o.pose.orientation},
                       Eigen::Vector3d::Constant(2.0 * s.x()), c);
      }
    } else if (o.shape == "plane") {  // a half-space: its surface drawn 1 m wide, 1 mm thick, just under it
      const Pose surface{o.pose.position - 0.0005 * (o.pose.orientation * Eigen::Vector3d::UnitZ()),
                         o.pose.orientation};
      append_sized(cubes, cubes.empty(), surface, Eigen::Vector3d(1.0, 1.0, 0.001), c);
    } else if (!o.corners.empty()) {  // a mesh: its triangles in its frame
      if (!triangles.empty()) triangles += ',';
      triangles += "{\"pose\":";
      append_pose(triangles, o.pose);
      triangles += ",\"points\":[";
      const std::size_t count = o.corners.size() / 3;
      const std::size_t step = (count + max_triangles - 1) / max_triangles;
      for (std::size_t i = 0; i < o.corners.size(); ++i) {
        if ((i / 3) % step != 0) continue;
        if (i > 0) triangles += ',';
        triangles += "{\"x\":";
        append_number(triangles, o.corners[i].x());
        triangles += ",\"y\":";
        append_number(triangles, o.corners[i].y());
        triangles += ",\"z\":";
        append_number(triangles, o.corners[i].z());
        triangles += '}';
      }
      triangles += "],\"color\":";
      append_colour(triangles, c);
      triangles += ",\"colors\":[],\"indices\":[]}";
    }
  }
  scene_json::begin_entity(out, first, time_ns, std::string("haptic_scene/") + which);
  out += ",\"cubes\":[" + cubes + "],\"spheres\":[" + spheres + "],\"cylinders\":[" + cylinders + "],\"triangles\":[" +
         triangles + "]";
  scene_json::empty_lists(out, {"arrows", "lines", "texts", "models"});
  scene_json::end_entity(out);
}

void append_proxies(std::string& out, std::uint64_t time_ns, const SceneDrawing& d) {
  std::string spheres;
  for (const SceneProxyDrawing& p : d.proxies)
    append_sized(spheres, spheres.empty(), Pose{p.position, Eigen::Quaterniond::Identity()},
                 Eigen::Vector3d::Constant(2.0 * p.radius), p.touching ? kTouching : kProxy);
  scene_json::begin_entity(out, false, time_ns, "haptic_scene/proxies");
  out += ",\"spheres\":[" + spheres + "]";
  scene_json::empty_lists(out, {"arrows", "cubes", "cylinders", "lines", "triangles", "texts", "models"});
  scene_json::end_entity(out);
}

// What the still objects look like now: their names, shapes and poses.
std::string still_signature(const SceneDrawing& d) {
  std::string s;
  for (const SceneObjectDrawing& o : d.objects)
    if (!o.moving)
      s += fmt::format("{}:{}:{}:{:.6f},{:.6f},{:.6f};", o.name, o.shape, o.triangles, o.pose.position.x(),
                       o.pose.position.y(), o.pose.position.z());
  return s;
}

}  // namespace

void append_scene_entities(std::string& out, std::uint64_t time_ns, const SceneDrawing& d, bool with_still) {
  out = "{\"deletions\":[],\"entities\":[";
  append_objects(
      out, true, time_ns, "moving", d, [](const SceneObjectDrawing& o) { return o.moving; }, kMoving,
      kMaxMovingTriangles);
  if (with_still)
    append_objects(
        out, false, time_ns, "still", d, [](const SceneObjectDrawing& o) { return !o.moving; }, kStill,
        HapticSceneView::kMaxTriangles);
  append_proxies(out, time_ns, d);
  out += "]}";
}

void HapticSceneView::scene_update(std::uint64_t time_ns, std::int64_t now_ns, std::string& out) {
  SceneDrawing d = scene_.drawing(kMaxTriangles);
  std::string signature = still_signature(d);
  const bool still = !sent_ || signature != still_signature_ || now_ns - still_sent_ns_ >= kStillEveryNs;
  if (still) {
    still_signature_ = std::move(signature);
    still_sent_ns_ = now_ns;
    sent_ = true;
  }
  append_scene_entities(out, time_ns, d, still);
}

}  // namespace hapticd::server::live_view
