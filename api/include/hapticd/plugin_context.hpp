#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "hapticd/device_description.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd {
namespace model {
class RobotModel;
}  // namespace model
class SceneService;

// What the server tells a plugin at configure() time besides its parameters.
struct PluginContext {
  std::string device_name;                    // the device this plugin serves, as named in the session file
  const DeviceDescription* device = nullptr;  // the configured device (null when configuring the device itself)
  // The device's robot model (DeviceDescription::robot_model_file), parsed once by the server for the whole
  // chain and mounted at base_pose (RobotModel::with_base): its poses, Jacobians and gravity are in the world
  // frame. Null without one (or when configuring the device itself). It outlives the plugin.
  const model::RobotModel* robot_model = nullptr;
  // The device's base in the session's world frame (the session file's `base_pose`). A device plugin with a
  // model of its own mounts it there (a simulation then feels gravity as the mounted device would); a plugin
  // with geometry of its own in the device's frame maps world poses through it.
  Pose base_pose;
  double rate_hz = 2000.0;                 // control rate of the loop the plugin will run in
  std::uint64_t seed = 0;                  // seed for any randomness (deterministic per session and device)
  std::filesystem::path config_directory;  // folder of the session file: relative paths resolve against it
  // The session's haptic scene (its `scene` section; hapticd/scene_service.hpp), shared by its devices and edited
  // at run time: a virtual model that renders it takes a reader of it. Null without the section. It outlives the
  // plugin.
  SceneService* scene = nullptr;
};

}  // namespace hapticd
