#pragma once
// From a validated session file to configured device sessions: loads each plugin, checks its parameters
// against the plugin's schema, configures it. Every failure is a ConfigError located in the session file.
#include <memory>
#include <vector>

#include "config/session_config.hpp"
#include "plugins/plugin_loader.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

std::vector<std::unique_ptr<DeviceSession>> build_sessions(const SessionConfig& config, PluginLoader& loader);

// Per-device seed derived from the session seed (splitmix64), so devices get independent random streams.
std::uint64_t device_seed(std::uint64_t session_seed, std::size_t device_index) noexcept;

}  // namespace hapticd::server
