#pragma once
// One device as the live view shows it (docs/live-view.md): from a snapshot of the loop, the JSON messages of its
// three channels - the frame transforms of every link of its robot model and of the handle, target and proxy
// (foxglove.FrameTransforms); its 3-D scene: the links drawn as a skeleton, the handle, target and proxy, the
// operator's and the rendered wrench as arrows (foxglove.SceneUpdate); and its state for plots
// (hapticd.DeviceState). Runs on the live view's thread, never on the loop.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hapticd/device_description.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/robot_model.hpp"
#include "session/device_snapshot.hpp"

namespace hapticd::server::live_view {

struct DeviceViewSettings {
  double force_scale_m_per_n = 0.005;  // arrow length per newton
};

class DeviceView {
 public:
  // model: the device's robot model (null: none - only the handle, target and proxy are shown).
  DeviceView(std::string device, const DeviceDescription& description, std::shared_ptr<const model::RobotModel> model,
             std::vector<std::string> schemes, DeviceViewSettings settings);

  [[nodiscard]] const std::string& device() const noexcept { return device_; }
  // The frame a link (or named frame) of the model has in the view: "<device>/<link>"; the world is "world".
  [[nodiscard]] std::string frame_of(const std::string& link) const { return device_ + "/" + link; }

  // Each replaces `out` with the message for `s`, stamped `time_ns` (wall clock, ns since the epoch).
  void frame_transforms(const DeviceSnapshot& s, std::uint64_t time_ns, std::string& out);
  void scene_update(const DeviceSnapshot& s, std::uint64_t time_ns, std::string& out);
  void device_state(const DeviceSnapshot& s, std::uint64_t time_ns, std::string& out) const;

 private:
  void compute_posture(const DeviceSnapshot& s);

  std::string device_;
  std::vector<std::string> joint_names_;
  std::shared_ptr<const model::RobotModel> model_;
  std::unique_ptr<model::ModelData> data_;
  std::vector<int> skeleton_;  // the model's frames from the base to the handle, in chain order
  std::vector<std::string> schemes_;
  DeviceViewSettings settings_;
  std::uint64_t posture_cycle_ = ~std::uint64_t{0};  // the snapshot data_ was computed for
};

}  // namespace hapticd::server::live_view
