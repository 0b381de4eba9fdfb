#pragma once
// The engines' worlds for the live view (hapticd_world, docs/live-view.md): a reader in the default partition,
// taken on Cyclone's receive thread; each world is checked (dds::check_world) - a malformed one is dropped and
// counted, never drawn - and handed to the sink (the live view). Made only when the session has a live view.
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>

#include "hapticd/dds/endpoints.hpp"
#include "hapticd_msg.h"

namespace hapticd::server {

class WorldRelay {
 public:
  using Sink = std::function<void(const hapticd_msg_World&)>;
  WorldRelay(const dds::Participant& participant, Sink sink);
  ~WorldRelay();
  WorldRelay(const WorldRelay&) = delete;
  WorldRelay& operator=(const WorldRelay&) = delete;

  [[nodiscard]] std::uint64_t accepted() const noexcept { return accepted_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t rejected() const noexcept { return rejected_.load(std::memory_order_relaxed); }

 private:
  void take();

  Sink sink_;
  std::mutex take_mutex_;
  std::atomic<std::uint64_t> accepted_{0}, rejected_{0};
  dds::Reader<hapticd_msg_World> reader_;  // last: its listener may run at once
};

}  // namespace hapticd::server
