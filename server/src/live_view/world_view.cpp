#include "live_view/world_view.hpp"

#include <fmt/format.h>

#include <vector>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/json_text.hpp"
#include "live_view/scene_json.hpp"

namespace hapticd::server::live_view {

using namespace json_text;
using namespace scene_json;

namespace {

// One world's entity: its shapes as cubes, spheres and cylinders (a capsule: a cylinder and two spheres; a plane: a
// thin cube, 2 m across when unbounded).
void append_world(std::string& out, bool first, std::uint64_t time_ns, const std::string& engine,
                  const hapticd_msg_World& w) {
  // Each body once in the metadata, with the colour of its first shape ("r g b" in 0..1): a viewer's legend.
  std::string metadata;
  for (int i = 0; i < w.shape_count; ++i) {
    const std::string body(dds::text_of(w.shapes[i].body));
    bool seen = false;
    for (int k = 0; k < i && !seen; ++k) seen = body == dds::text_of(w.shapes[k].body);
    if (seen) continue;
    if (!metadata.empty()) metadata += ',';
    metadata += "{\"key\":";
    append_string(metadata, body);
    metadata += ",\"value\":";
    append_string(metadata, fmt::format("{:.3f} {:.3f} {:.3f}", w.shapes[i].color[0], w.shapes[i].color[1],
                                        w.shapes[i].color[2]));
    metadata += '}';
  }
  begin_entity(out, first, time_ns, "world/" + engine, metadata);
  std::string cubes, spheres, cylinders;
  for (int i = 0; i < w.shape_count; ++i) {
    const hapticd_msg_WorldShape& s = w.shapes[i];
    Pose pose = dds::to_pose(s.shape_pose);
    pose.orientation.normalize();  // check_world lets through a norm within 0.5..2
    const Eigen::Vector3d size(s.size[0], s.size[1], s.size[2]);
    const Rgba c{s.color[0], s.color[1], s.color[2], s.color[3]};
    switch (s.shape) {
      case hapticd_msg_SHAPE_BOX:
        append_sized(cubes, cubes.empty(), pose, 2.0 * size, c);
        break;
      case hapticd_msg_SHAPE_SPHERE:
        append_sized(spheres, spheres.empty(), pose, Eigen::Vector3d::Constant(2.0 * size.x()), c);
        break;
      case hapticd_msg_SHAPE_ELLIPSOID:
        append_sized(spheres, spheres.empty(), pose, 2.0 * size, c);
        break;
      case hapticd_msg_SHAPE_CYLINDER:
        append_sized(cylinders, cylinders.empty(), pose, Eigen::Vector3d(2 * size.x(), 2 * size.x(), 2 * size.y()), c,
                     true);
        break;
      case hapticd_msg_SHAPE_CAPSULE: {
        append_sized(cylinders, cylinders.empty(), pose, Eigen::Vector3d(2 * size.x(), 2 * size.x(), 2 * size.y()), c,
                     true);
        const Eigen::Vector3d axis = pose.orientation * Eigen::Vector3d::UnitZ();
        for (const double end : {-1.0, 1.0}) {
          append_sized(spheres, spheres.empty(), Pose{pose.position + end * size.y() * axis, pose.orientation},
                       Eigen::Vector3d::Constant(2.0 * size.x()), c);
        }
        break;
      }
      default: {  // a plane
        const Eigen::Vector3d extent(size.x() > 0.0 ? 2.0 * size.x() : 2.0, size.y() > 0.0 ? 2.0 * size.y() : 2.0,
                                     0.001);
        append_sized(cubes, cubes.empty(), pose, extent, c);
      }
    }
  }
  out += ",\"cubes\":[" + cubes + "],\"spheres\":[" + spheres + "],\"cylinders\":[" + cylinders + "]";
  empty_lists(out, {"arrows", "lines", "triangles", "texts", "models"});
  end_entity(out);
}

}  // namespace

void WorldView::take(const hapticd_msg_World& world, std::int64_t now_ns) {
  const std::string engine(dds::text_of(world.engine));
  std::lock_guard lock(mutex_);
  auto it = engines_.find(engine);
  if (it == engines_.end()) {
    if (engines_.size() >= kMaxEngines) {
      ++dropped_;
      return;
    }
    it = engines_.emplace(engine, Entry{std::make_unique<hapticd_msg_World>(), 0, false}).first;
  }
  if (it->second.received_ns > 0 && world.serial <= it->second.world->serial) return;  // old, or repeated
  *it->second.world = world;
  it->second.received_ns = now_ns;
  it->second.changed = true;
  ++taken_;
}

bool WorldView::scene_update(std::uint64_t time_ns, std::int64_t now_ns, std::string& out) {
  std::vector<std::string> gone;
  std::vector<std::pair<std::string, const hapticd_msg_World*>> changed;
  std::lock_guard lock(mutex_);
  for (auto it = engines_.begin(); it != engines_.end();) {
    if (now_ns - it->second.received_ns > kForgetAfterNs) {
      gone.push_back(it->first);
      it = engines_.erase(it);
      continue;
    }
    if (it->second.changed) changed.emplace_back(it->first, it->second.world.get());
    it->second.changed = false;
    ++it;
  }
  if (gone.empty() && changed.empty()) return false;
  out = "{\"deletions\":[";
  for (std::size_t i = 0; i < gone.size(); ++i) {
    if (i > 0) out += ',';
    out += "{\"timestamp\":";
    append_time(out, time_ns);
    out += ",\"type\":0,\"id\":";
    append_string(out, "world/" + gone[i]);
    out += '}';
  }
  out += "],\"entities\":[";
  for (std::size_t i = 0; i < changed.size(); ++i)
    append_world(out, i == 0, time_ns, changed[i].first, *changed[i].second);
  out += "]}";
  return true;
}

std::uint64_t WorldView::taken() const {
  std::lock_guard lock(mutex_);
  return taken_;
}
std::uint64_t WorldView::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace hapticd::server::live_view
