#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "hapticd/device_description.hpp"

namespace hapticd {

// What the server tells a plugin at configure() time besides its parameters.
struct PluginContext {
  std::string device_name;                    // the device this plugin serves, as named in the session file
  const DeviceDescription* device = nullptr;  // the configured device (null when configuring the device itself)
  double rate_hz = 2000.0;                    // control rate of the loop the plugin will run in
  std::uint64_t seed = 0;                     // seed for any randomness (deterministic per session and device)
  std::filesystem::path config_directory;     // folder of the session file: relative paths resolve against it
};

}  // namespace hapticd
