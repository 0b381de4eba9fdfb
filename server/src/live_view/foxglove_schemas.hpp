#pragma once
// The JSON Schemas the live view advertises with its channels: two of Foxglove's well-known message schemas (the
// names make Foxglove's and Lichtblick's 3-D panel draw them) and the device state of our own (docs/live-view.md
// lists its fields; the Plot and Raw Message panels show it).
#include <string>

namespace hapticd::server::live_view {

inline constexpr const char* kFrameTransformsName = "foxglove.FrameTransforms";
inline constexpr const char* kSceneUpdateName = "foxglove.SceneUpdate";
inline constexpr const char* kDeviceStateName = "hapticd.DeviceState";

[[nodiscard]] std::string frame_transforms_schema();
[[nodiscard]] std::string scene_update_schema();
[[nodiscard]] std::string device_state_schema();

}  // namespace hapticd::server::live_view
