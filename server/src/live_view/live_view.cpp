#include "live_view/live_view.hpp"

#include <chrono>
#include <cmath>

#include "live_view/foxglove_schemas.hpp"
#include "live_view/viewer_page.hpp"

namespace hapticd::server::live_view {

namespace {

std::vector<Channel> channels_of(const std::vector<DeviceSession*>& devices, bool with_scene) {
  std::vector<Channel> channels;
  const std::string transforms = frame_transforms_schema(), scene = scene_update_schema(),
                    state = device_state_schema();
  for (std::size_t d = 0; d < devices.size(); ++d) {
    const std::string prefix = "/" + devices[d]->name();
    channels.push_back({LiveView::channel_id(d, 0), prefix + "/transforms", kFrameTransformsName, transforms});
    channels.push_back({LiveView::channel_id(d, 1), prefix + "/scene", kSceneUpdateName, scene});
    channels.push_back({LiveView::channel_id(d, 2), prefix + "/state", kDeviceStateName, state});
  }
  channels.push_back({LiveView::channel_id(devices.size(), 0), "/world/scene", kSceneUpdateName, scene});
  if (with_scene)
    channels.push_back({LiveView::channel_id(devices.size(), 1), "/haptic_scene/scene", kSceneUpdateName, scene});
  return channels;
}

std::int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::int64_t wall_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

LiveView::LiveView(const LiveViewSettings& settings, const std::vector<DeviceSession*>& devices, double loop_rate_hz,
                   const std::string& session_name, SceneService* scene)
    : address_(settings.address),
      scene_(scene != nullptr ? std::make_unique<HapticSceneView>(*scene) : nullptr),
      rate_hz_(settings.rate_hz) {
  FoxgloveServerOptions options;
  options.address = settings.address;
  options.port = settings.port;
  options.max_clients = settings.max_clients;
  options.allowed_origins = settings.allowed_origins;
  options.page = viewer_page();
  options.name = "hapticd: " + session_name;
  server_ = std::make_unique<FoxgloveServer>(options, channels_of(devices, scene != nullptr));
  const auto interval = static_cast<std::uint64_t>(std::max(1.0, std::round(loop_rate_hz / settings.rate_hz)));
  sources_.reserve(devices.size());
  for (DeviceSession* d : devices) {
    std::vector<std::string> schemes;
    for (const SchemeChain& s : d->chain().schemes) schemes.push_back(s.name);
    sources_.push_back(Source{&d->status(),
                              DeviceView(d->name(), d->description(), d->chain().robot_model, std::move(schemes),
                                         DeviceViewSettings{settings.force_scale_m_per_n}),
                              DeviceSnapshot{}});
    d->set_view_interval(interval);
  }
}

LiveView::~LiveView() { stop(); }

void LiveView::start() {
  // Twice the snapshots' rate: each is sent soon after the loop made it, whatever the two clocks' phase.
  server_->start(std::chrono::nanoseconds(static_cast<std::int64_t>(0.5e9 / rate_hz_)), [this] { tick(); });
}

void LiveView::stop() { server_->stop(); }

std::string LiveView::url() const {
  const bool v6 = address_.find(':') != std::string::npos;
  return "ws://" + (v6 ? "[" + address_ + "]" : address_) + ":" + std::to_string(server_->port());
}

void LiveView::take_world(const hapticd_msg_World& world) { world_.take(world, steady_now_ns()); }

void LiveView::tick() {
  if (server_->subscribed(world_channel_id())) {
    const auto time_ns = static_cast<std::uint64_t>(wall_now_ns());
    if (world_.scene_update(time_ns, steady_now_ns(), message_))
      server_->publish(world_channel_id(), time_ns, message_);
  }
  if (scene_ && server_->subscribed(scene_channel_id())) {
    const auto time_ns = static_cast<std::uint64_t>(wall_now_ns());
    scene_->scene_update(time_ns, steady_now_ns(), message_);
    server_->publish(scene_channel_id(), time_ns, message_);
  }
  for (std::size_t d = 0; d < sources_.size(); ++d) {
    Source& s = sources_[d];
    if (!s.status->take_view_snapshot(s.snapshot)) continue;
    if (!s.seen) {
      s.epoch_offset_ns = wall_now_ns() - s.snapshot.time_ns;
      s.seen = true;
    }
    const auto time_ns = static_cast<std::uint64_t>(s.epoch_offset_ns + s.snapshot.time_ns);
    if (server_->subscribed(channel_id(d, 0))) {
      s.view.frame_transforms(s.snapshot, time_ns, message_);
      server_->publish(channel_id(d, 0), time_ns, message_);
    }
    if (server_->subscribed(channel_id(d, 1))) {
      s.view.scene_update(s.snapshot, time_ns, message_);
      server_->publish(channel_id(d, 1), time_ns, message_);
    }
    if (server_->subscribed(channel_id(d, 2))) {
      s.view.device_state(s.snapshot, time_ns, message_);
      server_->publish(channel_id(d, 2), time_ns, message_);
    }
  }
}

}  // namespace hapticd::server::live_view
