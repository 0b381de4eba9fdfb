#pragma once
// The `teleoperation` section (docs/teleoperation.md): this server's device as one side of a bilateral link to
// a device of another server - the master the operator holds, or the remote in its environment. The link travels
// over the DDS interface (the `dds` section), so both servers share a domain. Absent: none.
#include <yaml-cpp/yaml.h>

#include <string>

#include "hapticd/parameters.hpp"
#include "hapticd/teleop/teleop_side.hpp"

namespace hapticd::server {

struct TeleoperationSettings {
  bool enabled = false;
  std::string device;  // this server's device on the link ("": the session's only device)
  std::string peer;    // the other server's device
  teleop::Role role = teleop::Role::master;
  teleop::LinkSettings link;
  int line = 0;  // of the section (errors found later, against the devices, name it)
};

// The section's schema: validates it and documents it (hapticd --describe-config).
ParameterSchema teleoperation_settings_schema();
// Reads the section (an undefined node: not enabled). Throws ConfigError naming the file, line and key.
TeleoperationSettings read_teleoperation(const YAML::Node& node, const std::string& file);

}  // namespace hapticd::server
