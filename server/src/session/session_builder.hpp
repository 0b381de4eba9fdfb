#pragma once
// From a validated session file to configured device sessions: loads each plugin, checks its parameters
// against the plugin's schema, configures it. Every failure is a ConfigError located in the session file.
#include <memory>
#include <vector>

#include "config/config_error.hpp"
#include "config/session_config.hpp"
#include "plugins/plugin_loader.hpp"
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

// Per-device seed derived from the session seed (splitmix64), so devices get independent random streams.
std::uint64_t device_seed(std::uint64_t session_seed, std::size_t device_index) noexcept;

}  // namespace hapticd::server
