#include "gate/scene_gate.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hapticd::server {

SceneGate::Reply SceneGate::apply(const Edit& e, const Sender& sender, std::string_view client, std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  Reply reply;
  const bool mine = !owner_.empty() && owner_channel_.peer == sender.peer;
  if (e.op == Op::list) {
    reply.objects = scene_.objects();
    reply.accepted = true;
    reply.message = std::to_string(reply.objects->size()) + " objects";
    return reply;  // a question, not an edit: not counted
  } else if (e.op == Op::contacts) {
    reply.contacts = scene_.contacts();
    reply.accepted = true;
    reply.message = std::to_string(reply.contacts->size()) + " contacts";
    return reply;
  } else if (e.op == Op::draw) {
    return draw(e);
  } else if (e.op == Op::claim) {
    if (owner_.empty() || mine) {
      owner_ = std::string(client);
      owner_channel_ = sender;
      reply = {true, "the scene is yours"};
    } else {
      reply.message = "the scene is claimed by '" + owner_ + "'";
    }
  } else if (!mine) {
    reply.message = owner_.empty() ? "claim the scene first" : "the scene is claimed by '" + owner_ + "'";
  } else if (e.op == Op::release) {
    owner_.clear();
    owner_channel_ = {};
    uploads_.clear();
    reply = {true, "released"};
  } else if (e.op == Op::upload) {
    reply = take_part(e);  // not a remake: bounded by the door's message rate and the upload's caps
  } else {
    if (e.op != Op::move) {  // a remake of the scene: within the rate
      allowance_ = std::min(kRemakesPerSecond,
                            allowance_ + static_cast<double>(now_ns - refilled_ns_) * 1e-9 * kRemakesPerSecond);
      refilled_ns_ = now_ns;
      if (allowance_ < 1.0) {
        rate_limited_.fetch_add(1, std::memory_order_relaxed);
        refused_.fetch_add(1, std::memory_order_relaxed);
        return {false, "more than 50 adds, removals and material changes a second: refused"};
      }
      allowance_ -= 1.0;
    }
    reply = edit(e);
  }
  (reply.accepted ? edits_ : refused_).fetch_add(1, std::memory_order_relaxed);
  return reply;
}

SceneGate::Reply SceneGate::draw(const Edit& e) {
  Reply reply;
  SceneDrawing d = scene_.drawing(e.name.empty() ? 0 : std::min(e.max_triangles, kMaxDrawTriangles));
  if (e.name.empty()) {
    reply.message = std::to_string(d.objects.size()) + " objects, " + std::to_string(d.proxies.size()) + " proxies";
  } else {
    const auto found =
        std::find_if(d.objects.begin(), d.objects.end(), [&](const auto& o) { return o.name == e.name; });
    if (found == d.objects.end()) return {false, "no object named '" + std::string(e.name) + "'"};
    SceneObjectDrawing o = std::move(*found);
    reply.drawn = o.corners.size() / 3;
    const std::size_t first = std::min(e.first, reply.drawn);
    const std::size_t last = std::min(first + kDrawPage, reply.drawn);
    o.corners = std::vector<Eigen::Vector3f>(o.corners.begin() + static_cast<std::ptrdiff_t>(3 * first),
                                             o.corners.begin() + static_cast<std::ptrdiff_t>(3 * last));
    d.objects.assign(1, std::move(o));
    d.proxies.clear();
    reply.message = "triangles " + std::to_string(first) + " to " + std::to_string(last) + " of " +
                    std::to_string(reply.drawn) + " drawn";
  }
  reply.accepted = true;
  reply.drawing = std::move(d);
  return reply;  // a question: not counted
}

SceneGate::Reply SceneGate::edit(const Edit& e) {
  try {
    switch (e.op) {
      case Op::add:
        if (!e.upload.empty()) return add_upload(e);
        scene_.add(e.text);
        return {true, "added"};
      case Op::remove:
        scene_.remove(e.name);
        return {true, "removed"};
      case Op::material:
        scene_.set_material(e.name, e.text);
        return {true, "its material set"};
      case Op::move:
        scene_.move(e.name, e.pose);
        return {true, "moved"};
      default:
        return {false, "not an edit"};
    }
  } catch (const std::exception& ex) {  // the scene's reason (an edit never reaches the loop unless it was whole)
    return {false, ex.what()};
  }
}

SceneGate::Reply SceneGate::take_part(const Edit& e) {
  const std::string name(e.upload);
  if (name.empty() || name.size() > 64) return {false, "an upload needs a name of 1 to 64 characters"};
  if (e.parts < 1 || e.parts > kMaxUploadParts)
    return {false, "upload '" + name + "': parts must be 1 to " + std::to_string(kMaxUploadParts)};
  if (e.vertices.size() % 3 != 0 || e.triangles.size() % 3 != 0)
    return {false, "upload '" + name + "': vertices and triangles come three numbers each"};
  for (const double v : e.vertices)
    if (!std::isfinite(v)) return {false, "upload '" + name + "': a vertex is not finite"};
  auto found = std::find_if(uploads_.begin(), uploads_.end(), [&](const Upload& u) { return u.name == name; });
  if (e.part == 0) {  // a new upload (again from the start, if one of that name was under way)
    if (found == uploads_.end()) {
      if (uploads_.size() >= kMaxUploads)
        return {false, "upload '" + name + "': " + std::to_string(kMaxUploads) +
                           " uploads are under way or waiting to be added; add or restart one"};
      found = uploads_.insert(uploads_.end(), Upload{});
    }
    *found = Upload{name, e.parts, 0, {}, {}};
  } else if (found == uploads_.end() || found->next != e.part || found->parts != e.parts) {
    const std::string expected = found == uploads_.end() ? "part 0 first"
                                 : found->next == found->parts
                                     ? "none: it is finished"
                                     : "part " + std::to_string(found->next) + " of " + std::to_string(found->parts);
    if (found != uploads_.end()) uploads_.erase(found);  // out of order: dropped whole
    return {false, "upload '" + name + "': part " + std::to_string(e.part) + " of " + std::to_string(e.parts) +
                       " out of order (expected " + expected + "); the upload is dropped"};
  }
  Upload& u = *found;
  std::size_t vertices = e.vertices.size() / 3, triangles = e.triangles.size() / 3;  // held with this part, in all
  for (const Upload& held : uploads_) {
    vertices += held.vertices.size() / 3;
    triangles += held.triangles.size() / 3;
  }
  if (vertices > kMaxUploadVertices || triangles > kMaxUploadTriangles) {
    uploads_.erase(found);
    return {false, "upload '" + name + "': the uploads would hold more than " + std::to_string(kMaxUploadVertices) +
                       " vertices or " + std::to_string(kMaxUploadTriangles) + " triangles; the upload is dropped"};
  }
  u.vertices.insert(u.vertices.end(), e.vertices.begin(), e.vertices.end());
  u.triangles.insert(u.triangles.end(), e.triangles.begin(), e.triangles.end());
  ++u.next;
  if (u.next < u.parts)
    return {true, "upload '" + name + "': part " + std::to_string(e.part) + " of " + std::to_string(e.parts)};
  return {true, "upload '" + name + "' finished: " + std::to_string(u.vertices.size() / 3) + " vertices, " +
                    std::to_string(u.triangles.size() / 3) + " triangles (add it as a mesh with upload: " + name + ")"};
}

SceneGate::Reply SceneGate::add_upload(const Edit& e) {
  const auto found =
      std::find_if(uploads_.begin(), uploads_.end(), [&](const Upload& u) { return u.name == e.upload; });
  if (found == uploads_.end() || found->next != found->parts)
    return {false, "no finished upload '" + std::string(e.upload) + "'"};
  std::vector<double> vertices = std::move(found->vertices);
  std::vector<std::uint32_t> triangles = std::move(found->triangles);
  uploads_.erase(found);  // taken, whether the mesh is good or not (a bad one is uploaded again)
  scene_.add_mesh(e.text, std::move(vertices), std::move(triangles));
  return {true, "added"};
}

bool SceneGate::check_claim(const std::function<bool(const Sender&)>& gone) {
  std::lock_guard lock(mutex_);
  if (owner_.empty() || !gone(owner_channel_)) return false;
  owner_.clear();
  owner_channel_ = {};
  uploads_.clear();
  return true;
}

std::string SceneGate::owner() const {
  std::lock_guard lock(mutex_);
  return owner_;
}

}  // namespace hapticd::server
