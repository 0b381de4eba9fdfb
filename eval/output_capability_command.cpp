#include "output_capability_command.hpp"

#include <fmt/format.h>
#include <fmt/os.h>

#include <cmath>
#include <numbers>

#include "device_presets.hpp"
#include "eval_options.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/output_capability.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  std::string device;
  std::string frame = "handle";
  std::vector<double> center, size, rotation_range, seed;
  int points = 5;
  int orientation_steps = 4;
  bool no_gravity = false;
  std::string task;
  std::string json;
};

std::vector<double> angles(double range_deg, int steps) {
  if (range_deg <= 0.0 || steps <= 1) return {0.0};
  std::vector<double> a;
  const double r = range_deg * std::numbers::pi / 180.0;
  const bool full_turn = range_deg >= 360.0 - 1e-9;
  for (int i = 0; i < steps; ++i) {
    a.push_back(full_turn ? -std::numbers::pi + 2 * std::numbers::pi * i / steps : -r / 2 + r * i / (steps - 1));
  }
  return a;
}

std::string vec_json(const Eigen::Vector3d& v) { return fmt::format("[{:.6g}, {:.6g}, {:.6g}]", v.x(), v.y(), v.z()); }

std::string worst_json(const model::WorstDirection& w, const Eigen::Vector3d& where, double mean) {
  return fmt::format(R"({{"worst": {:.6g}, "direction": {}, "limiting_joint": {}, "at_position": {}, "mean": {:.6g}}})",
                     w.value, vec_json(w.direction), w.limiting_joint + 1, vec_json(where), mean);
}

int run(const Options& o) {
  const std::filesystem::path urdf = find_device_urdf(o.device);
  const model::RobotModel robot = model::load_robot_model(urdf);
  const int frame = robot.require_frame(o.frame);

  DevicePreset preset;
  try {
    preset = device_preset(robot.name());
  } catch (const std::invalid_argument&) {
    if (o.center.empty() || o.size.empty()) throw;
    preset.name = robot.name();
    preset.seed.assign(static_cast<std::size_t>(robot.dof()), 0.0);
  }
  model::WorkspaceGrid grid;
  grid.center = o.center.empty() ? preset.workspace_center : Eigen::Vector3d(o.center[0], o.center[1], o.center[2]);
  grid.size = o.size.empty() ? preset.workspace_size : Eigen::Vector3d(o.size[0], o.size[1], o.size[2]);
  grid.points_per_axis = o.points;
  grid.free_orientation = preset.free_orientation && o.rotation_range.empty();
  const Eigen::Vector3d range = o.rotation_range.empty()
                                    ? preset.rotation_range_deg
                                    : Eigen::Vector3d(o.rotation_range[0], o.rotation_range[1], o.rotation_range[2]);
  const std::vector<double>& seed_values = o.seed.empty() ? preset.seed : o.seed;
  if (static_cast<int>(seed_values.size()) != robot.dof()) {
    throw std::invalid_argument(fmt::format("--seed needs {} joint values", robot.dof()));
  }
  JointVector seed(robot.dof());
  for (int i = 0; i < robot.dof(); ++i) seed[i] = seed_values[static_cast<std::size_t>(i)];
  model::ModelData data(robot);
  model::forward_kinematics(robot, data, seed);
  grid.nominal_orientation = model::frame_pose(robot, data, frame).linear();
  grid.orientation_offsets.clear();
  model::CapabilityOptions options;
  options.task = o.task.empty()            ? preset.task
                 : o.task == "translation" ? model::TaskRows::translation
                                           : model::TaskRows::full;
  // Orientation targets only where the device's task includes the orientation.
  const bool orientation_targets = !grid.free_orientation && options.task == model::TaskRows::full;
  const Eigen::Vector3d used_range = orientation_targets ? range : Eigen::Vector3d::Zero();
  for (double roll : angles(used_range.x(), o.orientation_steps)) {
    for (double pitch : angles(used_range.y(), o.orientation_steps > 1 ? 3 : 1)) {
      for (double yaw : angles(used_range.z(), o.orientation_steps))
        grid.orientation_offsets.emplace_back(roll, pitch, yaw);
    }
  }

  options.include_gravity = !o.no_gravity;
  std::vector<std::pair<std::string, model::GridCapability>> results;
  options.subspace = model::CapabilitySubspace::translation;
  results.emplace_back("translation", model::grid_output_capability(robot, frame, grid, seed, options));
  if (options.task == model::TaskRows::full) {
    options.subspace = model::CapabilitySubspace::rotation;
    results.emplace_back("rotation", model::grid_output_capability(robot, frame, grid, seed, options));
  }

  fmt::print("output capability of {} ({}), frame '{}', {} task, gravity {}\n", robot.name(), urdf.string(), o.frame,
             options.task == model::TaskRows::full ? "6-D" : "translational",
             options.include_gravity ? "included" : "ignored");
  fmt::print("grid: centre {} m, size {} m, {}^3 positions x {}\n", vec_json(grid.center), vec_json(grid.size),
             grid.points_per_axis,
             grid.free_orientation ? std::string("free orientation")
                                   : fmt::format("{} orientations", grid.orientation_offsets.size()));
  for (const auto& [name, r] : results) {
    const bool t = name == "translation";
    fmt::print("{:<11} reached {}/{} poses, worst task condition {:.3g}\n", name, r.reached, r.poses,
               r.worst_condition);
    fmt::print("  {:<13} worst {:9.3f} {:<7} (joint {}), mean {:9.3f}\n", t ? "force" : "torque", r.force.value,
               t ? "N" : "N m", r.force.limiting_joint + 1, r.mean_force);
    fmt::print("  {:<13} worst {:9.3f} {:<7} (joint {}), mean {:9.3f}\n", "velocity", r.velocity.value,
               t ? "m/s" : "rad/s", r.velocity.limiting_joint + 1, r.mean_velocity);
    fmt::print("  {:<13} worst {:9.3f} {:<7} (joint {}), mean {:9.3f}\n", "acceleration", r.acceleration.value,
               t ? "m/s^2" : "rad/s^2", r.acceleration.limiting_joint + 1, r.mean_acceleration);
  }
  if (!o.json.empty()) {
    auto out = fmt::output_file(o.json);
    out.print(R"({{"device": "{}", "urdf": "{}", "frame": "{}", "task": "{}", "include_gravity": {},)", robot.name(),
              urdf.string(), o.frame, options.task == model::TaskRows::full ? "full" : "translation",
              options.include_gravity);
    out.print(R"( "grid": {{"center": {}, "size": {}, "points_per_axis": {}, "orientations": {}}})",
              vec_json(grid.center), vec_json(grid.size), grid.points_per_axis, grid.orientation_offsets.size());
    for (const auto& [name, r] : results) {
      out.print(
          R"(, "{}": {{"poses": {}, "reached": {}, "worst_condition": {:.6g}, "force": {}, "velocity": {}, "acceleration": {}}})",
          name, r.poses, r.reached, r.worst_condition, worst_json(r.force, r.force_worst_position, r.mean_force),
          worst_json(r.velocity, r.velocity_worst_position, r.mean_velocity),
          worst_json(r.acceleration, r.acceleration_worst_position, r.mean_acceleration));
    }
    out.print("}}\n");
  }
  for (const auto& [name, r] : results) {
    if (r.reached == 0) {
      fmt::print(stderr, "hapticd-eval: no pose of the grid was reached ({})\n", name);
      return 1;
    }
  }
  return 0;
}

}  // namespace

void add_output_capability_command(CLI::App& app, int& exit_code) {
  auto options = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "output-capability",
      "Worst-direction peak force, velocity and acceleration of the handle over a workspace grid (appendix C)");
  cmd->add_option("--device", options->device, "vishard3, vishard6, vishard10 or a URDF file")->required();
  cmd->add_option("--frame", options->frame, "frame evaluated")->capture_default_str();
  cmd->add_option("--center", options->center, "workspace box centre x y z [m] (default: device preset)")->expected(3);
  cmd->add_option("--size", options->size, "workspace box edge lengths x y z [m]")->expected(3);
  cmd->add_option("--points", options->points, "grid points per box axis")
      ->check(CLI::Range(1, 50))
      ->capture_default_str();
  cmd->add_option("--orientation-steps", options->orientation_steps,
                  "steps per rotation axis with a nonzero range (pitch: 3)")
      ->check(CLI::Range(1, 36))
      ->capture_default_str();
  cmd->add_option("--rotation-range", options->rotation_range,
                  "full widths of roll, pitch, yaw about the world axes [deg]")
      ->expected(3);
  cmd->add_option("--seed", options->seed, "the position solver's start configuration");
  cmd->add_option("--task", options->task,
                  "rows the device controls: full (6-D) or translation (orientation free); default: preset")
      ->check(CLI::IsMember({"full", "translation"}));
  cmd->add_flag("--no-gravity", options->no_gravity, "do not reserve torque for holding the arm");
  cmd->add_option("--json", options->json, "write the results as JSON");
  cmd->callback([options, &exit_code] { exit_code = run(*options); });
}

}  // namespace hapticd::eval
