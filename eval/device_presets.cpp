#include "device_presets.hpp"

#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

namespace hapticd::eval {

DevicePreset device_preset(const std::string& name) {
  DevicePreset p;
  p.name = name;
  if (name == "vishard3") {
    // Translational device (passive gimbal): workspace 0.6 x 0.25 x 0.4 m in front of joint 1.
    p.task = model::TaskRows::translation;
    p.seed = {-0.3, 1.6, 0.0};
    p.workspace_center = {0.0, 0.40, 0.0};
    p.workspace_size = {0.6, 0.25, 0.4};
    // ../shared/spec/CONTROL-METHODS.md section 2: the thesis's IJC and TJC on ViSHaRD3.
    p.ijc_joint_inertia = {0.930, 0.416, 0.279};
    p.tjc_task_mass = {6.813, 9.350, 4.812};
    p.friction_file = "friction/vishard3.yaml";
  } else if (name == "vishard6") {
    // Workspace 0.86 x 0.3 x 0.3 m. Joints 1-3 are vertical, so the handle height is set by the wrist pitch
    // (joint 4) alone: height and pitch are coupled and a box x orientation grid is not reachable. The grid
    // takes positions only; the orientation follows from the nominal pose (docs/output-capability.md).
    p.seed = {-0.5, 1.0, -0.5, 0.0, 0.0, 0.0};
    p.workspace_center = {1.0, 0.0, 1.10};
    p.workspace_size = {0.3, 0.86, 0.3};
    p.free_orientation = true;
    // The shipped admittance sessions' start: the forearm across the pitched wrist, well conditioned in 6-D.
    p.rig_position = {-0.5, 1.0, -0.5, 0.5, 1.57, 0.0};
  } else if (name == "vishard10") {
    // Box of the simple inverse function, 0.85 x 0.71 m in the plane; the model's wrist reaches 0.42 m of
    // height (links 6 and 7), so the height evaluated is 0.3 m, not the published 0.6 m. 360 deg about
    // every axis (pitch limited to +-60 deg on the grid, see docs/output-capability.md).
    p.seed = {0.3, -0.6, 0.6, -0.6, 0.3, 1.0, -2.0, 1.0, 0.8, 0.0};
    p.workspace_center = {0.45, 0.0, 1.49};
    p.workspace_size = {0.85, 0.71, 0.3};
    p.rotation_range_deg = {360.0, 120.0, 360.0};
    // The thesis's computed torque ran on the partitioned solution's inverse functions (its q_d differentiated;
    // the SCARA pseudoinverse failed on the hardware, ../shared/spec/CONTROL-METHODS.md section 3), with the
    // SCARA's pair 1-2 along y: the published box of the inverse function, 0.85 x 0.71 m, is the speed limits'
    // rectangle at 1 m/s with pair 1-2 (joint 2, 5.67 rad/s: |u| <= 0.71) along y and pair 3-4 (joint 4,
    // 7.6 rad/s: 0.85) along x. The start: the functions' posture for the handle at (0.2, 0.15, 1.45) m, its
    // axis vertical (the shipped partitioned session's pose; docs/evaluation.md "ViSHaRD6 and ViSHaRD10").
    p.rig_position = {2.836900,  -2.532207, 4.819213,  -3.964626, -1.159279,
                      -1.146954, 2.293908,  -2.717751, 1.570796,  0.0};
    // The friction identification starts where it did before, the SCARA folded, the wrist at q8 = 1, q9 = 1.3
    // (at the rig's start joint 8 carries the wrist's weight through all its strokes).
    p.identification_position = {0.8, -1.6, 1.6, -1.6, 0.8, 1.0, -2.0, 1.0, 1.3, 0.0};
    p.inverse_kinematics = "vishard10_ik";
    p.inverse_kinematics_takes_task = false;
    p.inverse_kinematics_parameters =
        "scara: inverse_function, scara_axes_yaw_rad: 1.5707963267948966, wrist: inverse_function, q5_0_rad: 0.0";
  } else {
    throw std::invalid_argument("no evaluation preset for device '" + name +
                                "' (known: vishard3, vishard6, vishard10; give --center and --size for others)");
  }
  return p;
}

std::optional<std::filesystem::path> find_config_file(const std::filesystem::path& relative, std::string* tried) {
  namespace fs = std::filesystem;
  std::vector<fs::path> config_dirs;
  if (const char* env = std::getenv("HAPTICD_CONFIG_DIR")) config_dirs.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) config_dirs.push_back(exe.parent_path().parent_path() / HAPTICD_INSTALL_DATADIR / "hapticd" / "config");
  config_dirs.emplace_back(HAPTICD_SOURCE_CONFIG_DIR);
  for (const fs::path& dir : config_dirs) {
    const fs::path candidate = dir / relative;
    if (fs::is_regular_file(candidate)) return candidate;
    if (tried != nullptr) *tried += "\n  " + candidate.string();
  }
  return std::nullopt;
}

std::filesystem::path find_device_urdf(const std::string& name_or_path) {
  if (std::filesystem::is_regular_file(name_or_path)) return name_or_path;
  std::string tried;
  if (auto found = find_config_file(std::filesystem::path("urdf") / (name_or_path + ".urdf"), &tried)) return *found;
  throw std::invalid_argument("device '" + name_or_path + "': not a file, and none of these exists:" + tried);
}

}  // namespace hapticd::eval
