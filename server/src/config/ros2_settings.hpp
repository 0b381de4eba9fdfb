#pragma once
// The `ros2` section (docs/ros2.md): the session's devices on ROS 2's wire - each device's pose, twist, the
// operator's wrench, joint states or buttons, the TF tree and the robot description, on ROS 2's topics and types in
// the ROS domain given, loopback unless the `dds` section's network says otherwise. Absent: none.
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "hapticd/parameters.hpp"

namespace hapticd::server {

struct Ros2Settings {
  bool enabled = false;
  int domain_id = 0;                  // ROS_DOMAIN_ID
  double rate_hz = 250.0;             // each device's topics, at most the loop's rate
  std::string ns = "/hapticd";        // the topics' namespace: <ns>/<device>/pose
  std::string world_frame = "world";  // the frame id of the world (REP 105's "world"; rviz2's fixed frame)
  std::vector<std::string> commands;  // the devices given to ROS: claimed by ROS, commanded over its topics
  std::vector<int> command_lines;     // where each is named (an error found against the devices names it)
  int line = 0;                       // of the section (errors found later name it)
};

// The section's schema: validates it and documents it (hapticd --describe-config).
ParameterSchema ros2_settings_schema();
// Reads the section (an undefined node: not enabled; `ros2:` alone: on with the defaults). Throws ConfigError
// naming the file, line and key.
Ros2Settings read_ros2(const YAML::Node& node, const std::string& file);
// Whether `name` is a valid ROS 2 namespace: "/" and tokens of letters, digits and '_' (not starting with a
// digit) joined by '/' ("/hapticd", "/lab/arm_1"). The same rules, without the leading '/', for a frame id.
bool valid_ros2_namespace(const std::string& name);
bool valid_ros2_frame(const std::string& name);

}  // namespace hapticd::server
