#pragma once
// The session's live view (docs/live-view.md): a Foxglove WebSocket server with three channels per device -
// /<device>/transforms, /<device>/scene and /<device>/state - fed from the loop's view snapshots (a lock-free
// hand-off of their own, published every loop_rate / rate_hz cycles) on the server's own thread, and /world/scene:
// the worlds of the engines that publish one (hapticd_world, handed over by the DDS bridge); and /haptic_scene/scene
// for a session with a haptic scene (its objects and the devices' proxies). The loop never waits for it and does
// nothing more for it than copy a snapshot at that interval.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "config/session_config.hpp"
#include "live_view/device_view.hpp"
#include "live_view/foxglove_server.hpp"
#include "live_view/haptic_scene_view.hpp"
#include "live_view/world_view.hpp"
#include "session/device_session.hpp"

namespace hapticd::server::live_view {

class LiveView {
 public:
  // Binds the address and port (throws std::runtime_error naming them and the reason) and has every device
  // publish view snapshots; call before the loop starts.
  // scene: the session's haptic scene (null: none; no /haptic_scene/scene channel then).
  LiveView(const LiveViewSettings& settings, const std::vector<DeviceSession*>& devices, double loop_rate_hz,
           const std::string& session_name, SceneService* scene = nullptr);
  ~LiveView();
  LiveView(const LiveView&) = delete;
  LiveView& operator=(const LiveView&) = delete;

  void start();
  void stop();  // idempotent
  [[nodiscard]] std::string url() const;
  [[nodiscard]] const FoxgloveServerCounters& counters() const noexcept { return server_->counters(); }

  // The channel ids of device d: transforms 3d+1, scene 3d+2, state 3d+3; the engines' worlds after them.
  static std::uint32_t channel_id(std::size_t device, int which) noexcept {
    return static_cast<std::uint32_t>(3 * device + 1 + static_cast<std::size_t>(which));
  }
  [[nodiscard]] std::uint32_t world_channel_id() const noexcept { return channel_id(sources_.size(), 0); }
  [[nodiscard]] std::uint32_t scene_channel_id() const noexcept { return channel_id(sources_.size(), 1); }

  // Any thread (the DDS bridge's receive thread): an engine's world, checked (dds::check_world).
  void take_world(const hapticd_msg_World& world);
  [[nodiscard]] const WorldView& worlds() const noexcept { return world_; }

 private:
  void tick();

  struct Source {
    DeviceStatus* status;  // the device's face for other threads: the live view takes its view snapshots
    DeviceView view;
    DeviceSnapshot snapshot;
    std::int64_t epoch_offset_ns = 0;  // wall clock minus loop clock, set at the first snapshot
    bool seen = false;
  };
  std::vector<Source> sources_;
  std::string address_;
  std::unique_ptr<FoxgloveServer> server_;
  WorldView world_;
  std::unique_ptr<HapticSceneView> scene_;
  double rate_hz_;
  std::string message_;
};

}  // namespace hapticd::server::live_view
