#include "gate/scene_gate.hpp"

#include <algorithm>
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
    reply = {true, "released"};
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

SceneGate::Reply SceneGate::edit(const Edit& e) {
  try {
    switch (e.op) {
      case Op::add:
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

bool SceneGate::check_claim(const std::function<bool(const Sender&)>& gone) {
  std::lock_guard lock(mutex_);
  if (owner_.empty() || !gone(owner_channel_)) return false;
  owner_.clear();
  owner_channel_ = {};
  return true;
}

std::string SceneGate::owner() const {
  std::lock_guard lock(mutex_);
  return owner_;
}

}  // namespace hapticd::server
