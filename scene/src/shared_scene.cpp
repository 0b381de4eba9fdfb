#include "hapticd/scene/shared_scene.hpp"

#include <algorithm>
#include <stdexcept>

namespace hapticd::scene {

SharedScene::Reader::Reader(std::unique_ptr<Scene> first, std::string device)
    : current_(first.release()), tracks_(kMaxObjects), tracked_(kMaxObjects, 0), device_(std::move(device)) {}

void SharedScene::Reader::report_contacts(const ProxyState& proxy, double radius) noexcept {
  ContactReport report;
  for (int i = 0; i < proxy.contact_count; ++i) {
    const ProxyContact& c = proxy.contacts[static_cast<std::size_t>(i)];
    if (c.object < 0 || static_cast<std::size_t>(c.object) >= current_->objects.size()) continue;
    ObjectContact& o = report.contacts[static_cast<std::size_t>(report.count++)];
    const SceneObject& touched = current_->objects[static_cast<std::size_t>(c.object)];
    o.object = touched.uid;
    o.origin = touched.pose.translation();
    o.force = -c.force;  // the hand pushes the object as the object pushes the hand
    o.point = c.point;
  }
  report.reported = true;
  report.proxy = proxy.proxy;
  report.radius = radius;
  contacts_.publish(report);
}

bool SharedScene::Reader::refresh(std::int64_t now_ns) noexcept {
  bool changed = false;
  if (stash_ != nullptr && returned_.try_push(stash_)) stash_ = nullptr;
  // A new scene only while nothing waits to be handed back: the one left then always has a place (the ring, else
  // the stash), and an offer not taken now waits for the next refresh.
  if (stash_ == nullptr) {
    if (Scene* offer = offered_.exchange(nullptr, std::memory_order_acq_rel); offer != nullptr) {
      if (!returned_.try_push(current_)) stash_ = current_;
      current_ = offer;
      ++taken_;
      changed = true;
    }
  }
  for (SceneObject& o : current_->objects) {
    if (!o.moving) continue;
    PoseTrack& track = tracks_[o.slot];
    if (tracked_[o.slot] != o.uid) {  // a new object in this slot: its track starts where it was added
      track.restart(o.pose, now_ns, o.uid);
      tracked_[o.slot] = o.uid;
    }
    const PoseTrack::Played played = track.at(now_ns);
    o.pose = played.pose;
    o.velocity = played.velocity;
  }
  return changed;
}

SharedScene::SharedScene(Scene initial)
    : moved_(kMaxObjects, Eigen::Isometry3d::Identity()), slot_used_(kMaxObjects, 0) {
  if (initial.objects.size() > kMaxObjects)
    throw std::invalid_argument("a scene has at most " + std::to_string(kMaxObjects) + " objects");
  for (SceneObject& o : initial.objects) add(std::move(o));
}

SharedScene::~SharedScene() {
  for (auto& r : readers_) {
    Scene* s = nullptr;
    while (r->returned_.try_pop(s)) delete s;
    delete r->offered_.exchange(nullptr);
    delete r->stash_;
    delete r->current_;
  }
}

SharedScene::Reader& SharedScene::add_reader(std::string device) {
  std::lock_guard lock(mutex_);
  auto first = std::make_unique<Scene>(Scene{objects_});
  readers_.push_back(std::unique_ptr<Reader>(new Reader(std::move(first), std::move(device))));
  return *readers_.back();
}

std::size_t SharedScene::index_of(std::string_view name) const {
  for (std::size_t i = 0; i < objects_.size(); ++i)
    if (objects_[i].name == name) return i;
  throw std::invalid_argument("no object named '" + std::string(name) + "'");
}

void SharedScene::publish() {
  for (auto& r : readers_) {
    auto copy = std::make_unique<Scene>(Scene{objects_});
    delete r->offered_.exchange(copy.release(), std::memory_order_acq_rel);  // an offer not taken: never read
  }
  free_returned();
}

void SharedScene::free_returned() {
  Scene* s = nullptr;
  for (auto& r : readers_)
    while (r->returned_.try_pop(s)) delete s;
}

std::uint64_t SharedScene::add(SceneObject object) {
  std::lock_guard lock(mutex_);
  if (object.name.empty()) throw std::invalid_argument("an object needs a name");
  for (const SceneObject& o : objects_)
    if (o.name == object.name) throw std::invalid_argument("the name '" + object.name + "' is taken by another object");
  if (objects_.size() >= kMaxObjects)
    throw std::invalid_argument("the scene is full (" + std::to_string(kMaxObjects) + " objects)");
  std::size_t slot = 0;
  while (slot_used_[slot] != 0) ++slot;  // one is free: fewer objects than slots
  slot_used_[slot] = 1;
  object.slot = static_cast<std::uint32_t>(slot);
  object.uid = next_uid_++;
  moved_[slot] = object.pose;
  objects_.push_back(std::move(object));
  publish();
  return objects_.back().uid;
}

void SharedScene::remove(std::string_view name) {
  std::lock_guard lock(mutex_);
  const std::size_t i = index_of(name);
  slot_used_[objects_[i].slot] = 0;
  objects_.erase(objects_.begin() + static_cast<std::ptrdiff_t>(i));
  publish();
}

void SharedScene::set_material(std::string_view name, const Material& material) {
  std::lock_guard lock(mutex_);
  objects_[index_of(name)].material = material;
  publish();
}

void SharedScene::move(std::string_view name, const PoseUpdate& pose) {
  std::lock_guard lock(mutex_);
  const SceneObject& o = objects_[index_of(name)];
  if (!o.moving) throw std::invalid_argument("'" + o.name + "' was not made a moving object");
  PoseUpdate update = pose;
  update.object = o.uid;  // a pose still in the slot's track when another object takes the slot is not its
  for (auto& r : readers_) r->tracks_[o.slot].publish(update);
  moved_[o.slot] = Eigen::Translation3d(pose.position) * pose.orientation;
}

Scene SharedScene::drawn() const {
  std::lock_guard lock(mutex_);
  Scene out{objects_};
  for (SceneObject& o : out.objects)
    if (o.moving) o.pose = moved_[o.slot];
  return out;
}

std::vector<DeviceProxy> SharedScene::proxies() {
  std::lock_guard lock(mutex_);
  std::vector<DeviceProxy> out;
  for (auto& r : readers_) {
    (void)r->contacts_.take(r->last_contacts_);
    const ContactReport& c = r->last_contacts_;
    if (c.reported) out.push_back({r->device_, c.proxy, c.radius, c.count > 0});
  }
  return out;
}

Scene SharedScene::snapshot() const {
  std::lock_guard lock(mutex_);
  return Scene{objects_};
}

std::vector<DeviceContact> SharedScene::contacts() {
  std::lock_guard lock(mutex_);
  std::vector<DeviceContact> out;
  for (auto& r : readers_) {
    (void)r->contacts_.take(r->last_contacts_);  // nothing new: the last report stands
    for (int i = 0; i < r->last_contacts_.count; ++i) {
      const ObjectContact& c = r->last_contacts_.contacts[static_cast<std::size_t>(i)];
      const auto o =
          std::find_if(objects_.begin(), objects_.end(), [&](const SceneObject& x) { return x.uid == c.object; });
      if (o == objects_.end()) continue;  // removed since
      out.push_back({r->device_, o->name, c.object, c.force, c.point, c.origin});
    }
  }
  return out;
}

void SharedScene::collect() {
  std::lock_guard lock(mutex_);
  free_returned();
}

}  // namespace hapticd::scene
