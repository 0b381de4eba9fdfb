#pragma once
// What the evaluations assume per shipped device: where its URDF is, which task-space rows it controls,
// its nominal configuration and the workspace (box and orientation ranges) it is evaluated over.
// The workspace sizes are the published ones ([U06] device data (docs/references.md)); their placement is our choice,
// documented in docs/output-capability.md.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hapticd/joint_vector.hpp"
#include "hapticd/model/task_space.hpp"

namespace hapticd::eval {

struct DevicePreset {
  std::string name;
  model::TaskRows task = model::TaskRows::full;
  std::vector<double> seed;  // nominal configuration, the position solver's start
  Eigen::Vector3d workspace_center = Eigen::Vector3d::Zero();
  Eigen::Vector3d workspace_size = Eigen::Vector3d::Zero();
  // Orientation ranges about the world axes (full widths, degrees); all zero for translational devices.
  Eigen::Vector3d rotation_range_deg = Eigen::Vector3d::Zero();
  bool free_orientation = false;  // see WorkspaceGrid::free_orientation
  // The closed-loop experiments' rig: where the joints start (empty: `seed`), and the inverse kinematics a
  // joint-space scheme (computed torque) runs on (plugin name and its parameters, a YAML flow-mapping body
  // without the task).
  std::vector<double> rig_position;
  [[nodiscard]] const std::vector<double>& rig_start() const noexcept {
    return rig_position.empty() ? seed : rig_position;
  }
  // Where the friction identification starts (empty: rig_start()): a posture whose strokes leave the joints
  // unloaded long enough to compare the identified curves with the truth.
  std::vector<double> identification_position;
  std::string inverse_kinematics = "newton_ik";
  std::string inverse_kinematics_parameters;
  bool inverse_kinematics_takes_task = true;  // the rig adds `task:` (translation or full) to its parameters
  // The constant inertias of the Jacobian inner loops where the thesis gives them (its workspace means): IJC's
  // diagonal joint inertia M_hat [kg m^2] and TJC's diagonal task mass Mx_hat [kg]; empty: the plugins' own
  // (the diagonals at activation).
  std::vector<double> ijc_joint_inertia;
  std::vector<double> tjc_task_mass;
  // The device's identified friction (the config folder's friction file, docs/friction.md) that admittance
  // display's inner loops compensate; empty: none identified, the loops run uncompensated.
  std::string friction_file;
};

// The preset of a shipped device (vishard3, vishard6, vishard10); throws std::invalid_argument otherwise.
DevicePreset device_preset(const std::string& name);

// A file of the project's configuration (`relative` to the config folder: "friction/vishard3.yaml") in
// $HAPTICD_CONFIG_DIR, the installed share/hapticd/config or the source tree's config/, in that order; none if
// it is in none of them. `tried` (if given) lists the paths looked at.
std::optional<std::filesystem::path> find_config_file(const std::filesystem::path& relative,
                                                      std::string* tried = nullptr);

// The URDF of a device name or path: an existing file as given, else <config>/urdf/<name>.urdf with
// <config> = $HAPTICD_CONFIG_DIR, the installed share/hapticd/config, or the source tree's config/.
std::filesystem::path find_device_urdf(const std::string& name_or_path);

}  // namespace hapticd::eval
