#pragma once
// From a validated session file to configured device sessions: loads each plugin, checks its parameters
// against the plugin's schema, configures it. Every failure is a ConfigError located in the session file.
#include <memory>
#include <vector>

#include "config/config_error.hpp"
#include "config/session_config.hpp"
#include "group/group_stage.hpp"
#include "loader/plugin_loader.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

// A device whose plugin threw from configure() (a ParameterError is a session-file error and always fails).
struct ConfigureFailure {
  std::string device;
  ConfigError error;
  bool powered;  // false: the device plugin itself failed, the device is left out; true: held in its safe state
};

// An error in a value an override set names the override (SessionConfig::overrides). Without `report` every
// failure throws. With it, a plugin that throws from configure() isolates its device:
// the failure is added to `report`, the device is held in its safe state (or left out when its device plugin
// failed) and the others are built; the start fails only if no device can run.
std::vector<std::unique_ptr<DeviceSession>> build_sessions(const SessionConfig& config, PluginLoader& loader,
                                                           std::vector<ConfigureFailure>* report = nullptr);

// The stages of the session's device groups (`groups`), over the built devices (a device left out at start-up
// is left out of its group), with their models (`model`) loaded and configured. A group that checks distances
// needs robot models: a ConfigError otherwise; so is a model that cannot be loaded or configured.
std::vector<std::unique_ptr<GroupStage>> build_group_stages(const SessionConfig& config,
                                                            const std::vector<std::unique_ptr<DeviceSession>>& devices,
                                                            PluginLoader& loader);

// clock: device - the device whose ticks clock the loop: `server.clock_device`, else the one device that can
// (Device::clock()). A ConfigError at server.clock or server.clock_device when no device can, when the named one is
// not in the session or cannot, or when its stall watchdog is off (a device that stops ticking must stop the loop
// of a device a person holds). None for the other clocks.
struct ClockDevice {
  DeviceSession* device = nullptr;
  double stall_s = 0.0;  // its safety.max_stall_s: a tick this late is a stall
};
ClockDevice clock_device(const SessionConfig& config, const std::vector<DeviceSession*>& devices);

// Per-device seed derived from the session seed (splitmix64), so devices get independent random streams.
std::uint64_t device_seed(std::uint64_t session_seed, std::size_t device_index) noexcept;

}  // namespace hapticd::server
