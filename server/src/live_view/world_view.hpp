#pragma once
// The engines' worlds as the live view shows them (docs/live-view.md): an engine with a world of its own
// (hapticd-mujoco-engine) publishes its shapes on hapticd_world; the DDS bridge checks each world and hands it
// here; the live view's thread turns the newest of each engine into one scene entity ("world/<engine>") of the
// channel /world/scene, and deletes an engine's entity when it has not been heard for 2 s.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "hapticd_msg.h"

namespace hapticd::server::live_view {

class WorldView {
 public:
  static constexpr std::size_t kMaxEngines = 16;
  static constexpr std::int64_t kForgetAfterNs = 2'000'000'000;

  // Any thread (the bridge's DDS receive thread): keeps the newest world of its engine (a checked one:
  // dds::check_world). Worlds of more than kMaxEngines engines at once are dropped (counted).
  void take(const hapticd_msg_World& world, std::int64_t now_ns);
  // The live view's thread: replaces `out` with the scene update of what changed since the last call and returns
  // true, or returns false when nothing did.
  bool scene_update(std::uint64_t time_ns, std::int64_t now_ns, std::string& out);

  [[nodiscard]] std::uint64_t taken() const;
  [[nodiscard]] std::uint64_t dropped() const;

 private:
  struct Entry {
    std::unique_ptr<hapticd_msg_World> world;
    std::int64_t received_ns = 0;
    bool changed = false;
  };
  mutable std::mutex mutex_;
  std::map<std::string, Entry, std::less<>> engines_;
  std::uint64_t taken_ = 0, dropped_ = 0;
};

}  // namespace hapticd::server::live_view
