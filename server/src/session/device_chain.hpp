#pragma once
// What a device session is built from: the device plugin, its control schemes (each a chain virtual model ->
// inverse kinematics -> controller), and the device's settings. All configured at start-up (session_builder).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hapticd/model/robot_model.hpp"
#include "hapticd/plugin.hpp"
#include "loader/plugin_loader.hpp"
#include "safety/safety_settings.hpp"

namespace hapticd::server {

struct SchemeChain {
  std::string name;
  std::optional<PluginInstance<VirtualModel>> virtual_model;
  std::optional<PluginInstance<InverseKinematics>> inverse_kinematics;
  PluginInstance<Controller> controller;
};

// The session's haptic scene (its `scene` section; hapticd/scene_service.hpp), one for all its devices.
using SessionScene = std::shared_ptr<PluginInstance<SceneService>>;

struct DeviceChain {
  // The session's haptic scene (null without the section), shared by its devices: their virtual models read it
  // (PluginContext::scene), the doors edit it. First: destroyed after every plugin that reads it.
  SessionScene scene;
  // The device's robot model, parsed once (DeviceDescription::robot_model_file; null without one): the chain
  // state's estimator and every plugin of the chain (PluginContext::robot_model) use it. First: destroyed last.
  std::shared_ptr<const model::RobotModel> robot_model;
  PluginInstance<Device> device;
  // The device plugin's description, completed by the server (its base pose from the session file).
  DeviceDescription description;
  std::vector<SchemeChain> schemes;  // [0]: the scheme the device starts with
  double switch_ramp_s = 0.1;
  // Engine input older than the deadline fades out over the fade time (EngineInput::weight).
  double engine_deadline_s = 0.05;
  double engine_fade_s = 0.02;
  double engine_ramp_in_s = 0.1;  // engine input starting after a silence ramps in over this time
  SafetySettings safety;
  double period_s = 0.0005;  // the loop's period (the session's rate): filters and ramps are set up for it
  // The device's plugins could not all be configured (configure_error says why): the device is held in its
  // safe state from the first cycle, and may have no scheme.
  std::string configure_error;
};

}  // namespace hapticd::server
