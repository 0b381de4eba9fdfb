#pragma once
// The session file: server settings, and per device its plugin chain. Plugin parameters stay YAML here; they
// are checked against each plugin's own schema once the plugin is loaded (session/session_builder).
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hapticd/parameters.hpp"

namespace hapticd::server {

enum class ClockMode { realtime, lockstep };

struct ServerSettings {
  double rate_hz = 2000.0;
  ClockMode clock = ClockMode::realtime;
  double duration_s = 0.0;          // 0: until SIGINT/SIGTERM
  std::uint64_t seed = 1;
  int realtime_priority = 80;       // SCHED_FIFO priority; 0: do not ask
  bool lock_memory = true;
  int cpu = -1;                     // pin the loop thread to this CPU; -1: no pinning
  double shutdown_ramp_s = 0.2;     // torques ramp to zero over this time at the end of a session
  std::vector<std::filesystem::path> plugin_paths;  // resolved against the session file's folder
};

struct PluginConfig {
  std::string plugin;
  std::optional<std::string> library;
  YAML::Node parameters;   // validated later against the plugin's schema
  std::string key_path;    // "devices[0].controller"
  int line = 0;
};

// A control scheme: the plugin chain between the device's reading and its torques.
struct SchemeConfig {
  std::string name;
  std::optional<PluginConfig> virtual_model;
  std::optional<PluginConfig> inverse_kinematics;
  PluginConfig controller;
};

struct DeviceConfig {
  std::string name;
  PluginConfig device;
  // The scheme the device starts with (the device entry's own virtual_model / inverse_kinematics / controller,
  // named by its `scheme` key, "default" if absent).
  std::optional<PluginConfig> virtual_model;
  std::optional<PluginConfig> inverse_kinematics;
  PluginConfig controller;
  std::string scheme = "default";
  // Alternatives the device can switch to at run time (`schemes` list), configured at start-up.
  std::vector<SchemeConfig> alternatives;
  double switch_ramp_s = 0.1;  // a torque difference at a switch fades out over this time
};

struct SessionConfig {
  std::filesystem::path file;
  ServerSettings server;
  std::vector<DeviceConfig> devices;
};

// The schema of the `server` section: validates it and documents it (hapticd --describe-config).
ParameterSchema server_settings_schema();

// Reads and validates a session file. Throws ConfigError naming file, line and key.
SessionConfig load_session_config(const std::filesystem::path& file);

}  // namespace hapticd::server
