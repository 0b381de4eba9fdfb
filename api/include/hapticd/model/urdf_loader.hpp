#pragma once
// URDF -> RobotModel. The kinematic tree must be one serial chain of revolute/continuous/prismatic joints
// (at most kMaxJoints); fixed joints are merged into their parent body and kept as named frames; side
// branches of fixed links (sensor, handle) are frames as well. Drive data comes from the hapticd extension
// <hapticd_drive joint="..." .../> (docs/robot-models.md).
#include <filesystem>
#include <stdexcept>
#include <string>

#include "hapticd/export.hpp"
#include "hapticd/model/robot_model.hpp"

namespace hapticd::model {

// A model file that cannot be used; the message names the file and, where known, the line and element.
class HAPTICD_API ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[nodiscard]] HAPTICD_API RobotModel load_robot_model(const std::filesystem::path& urdf_file);
[[nodiscard]] HAPTICD_API RobotModel parse_robot_model(const std::string& urdf_text, const std::string& source_name);

}  // namespace hapticd::model
