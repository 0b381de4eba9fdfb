#include "config/ros2_settings.hpp"

#include <cctype>

#include "config/config_error.hpp"
#include "config/yaml_reader.hpp"

namespace hapticd::server {
namespace {

// Tokens of [A-Za-z0-9_], none empty nor starting with a digit, joined by '/' (ROS 2's names, design article
// "Topic and Service name mapping to DDS").
bool valid_tokens(const std::string& s, std::size_t from) {
  if (from >= s.size()) return false;
  bool token_start = true;
  for (std::size_t i = from; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '/') {
      if (token_start) return false;  // "//" or a '/' at the start of a token
      token_start = true;
    } else if (std::isalnum(c) != 0 || c == '_') {
      if (token_start && std::isdigit(c) != 0) return false;
      token_start = false;
    } else {
      return false;
    }
  }
  return !token_start;  // not ending in '/'
}

}  // namespace

bool valid_ros2_namespace(const std::string& name) {
  return name.size() <= 100 && !name.empty() && name[0] == '/' && valid_tokens(name, 1);
}
bool valid_ros2_frame(const std::string& name) { return name.size() <= 100 && valid_tokens(name, 0); }

ParameterSchema ros2_settings_schema() {
  const Ros2Settings d;
  ParameterSchema s;
  s.boolean("enabled", "publish the devices on ROS 2's topics").default_value(true);
  s.integer("domain_id", "the ROS domain (ROS_DOMAIN_ID of the ROS 2 nodes that listen)")
      .minimum(0)
      .maximum(232)
      .default_value(std::int64_t{d.domain_id});
  s.real("rate_hz", "each device's states per second on ROS 2's topics (at most the loop's rate)")
      .unit("Hz")
      .minimum(1.0)
      .maximum(10000.0)
      .default_value(d.rate_hz);
  s.string("namespace", "the topics' namespace: NAMESPACE/DEVICE/pose, ... (a ROS 2 namespace, e.g. /hapticd)")
      .default_value(d.ns);
  s.string("world_frame", "the frame id of the world frame (the TF tree's root; rviz2's fixed frame)")
      .default_value(d.world_frame);
  // commands: a list (read by read_ros2), documented here for --describe-config.
  return s;
}

Ros2Settings read_ros2(const YAML::Node& node, const std::string& file) {
  Ros2Settings r;
  if (!node.IsDefined()) return r;
  r.enabled = true;
  r.line = line_of(node);
  if (node.IsNull()) return r;  // `ros2:` alone: on with the defaults
  if (!node.IsMap()) throw ConfigError(file, line_of(node), "ros2", "expected a mapping of ROS 2 settings");
  const Parameters p = read_parameters(node, ros2_settings_schema(), file, "ros2", line_of(node), {"commands"});
  if (const YAML::Node c = node["commands"]; c.IsDefined()) {
    if (!c.IsSequence())
      throw ConfigError(file, line_of(c), "ros2.commands", "expected a list of device names ([vishard3])");
    for (const YAML::Node& d : c) {
      if (!d.IsScalar()) throw ConfigError(file, line_of(d), "ros2.commands", "expected a device name");
      r.commands.push_back(d.as<std::string>());
      r.command_lines.push_back(line_of(d));
    }
  }
  r.enabled = p.boolean("enabled");
  r.domain_id = static_cast<int>(p.integer("domain_id"));
  r.rate_hz = p.real("rate_hz");
  r.ns = p.string("namespace");
  r.world_frame = p.string("world_frame");
  if (!valid_ros2_namespace(r.ns))
    throw ConfigError(
        file, line_of(node["namespace"]), "ros2.namespace",
        "'" + r.ns + "' is not a ROS 2 namespace: '/' and names of letters, digits and '_' joined by '/'");
  if (!valid_ros2_frame(r.world_frame))
    throw ConfigError(file, line_of(node["world_frame"]), "ros2.world_frame",
                      "'" + r.world_frame + "' is not a frame id: names of letters, digits and '_' joined by '/'");
  return r;
}

}  // namespace hapticd::server
