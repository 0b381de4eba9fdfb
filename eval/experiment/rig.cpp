#include "rig.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "device_presets.hpp"

namespace hapticd::eval {
namespace {

void add_lines(std::string& out, const std::vector<std::string>& lines, const std::string& indent) {
  for (const std::string& line : lines) out += indent + line + "\n";
}

bool has_key(const std::vector<std::string>& lines, const std::string& key) {
  for (const std::string& line : lines)
    if (line.rfind(key + ":", 0) == 0) return true;
  return false;
}

}  // namespace

double shuttle_leg_s(double distance, double acceleration, double speed) {
  const double v = std::min(speed, std::sqrt(acceleration * distance));
  return 2.0 * v / acceleration + (distance - v * v / acceleration) / v;
}

std::string rig_yaml(const RigSpec& spec) {
  const DevicePreset preset = device_preset(spec.device.name);
  const bool translational = preset.task == model::TaskRows::translation;
  const std::vector<double>& q0 =
      spec.device.initial_position.empty() ? preset.rig_start() : spec.device.initial_position;
  const std::string task = translational ? "translation" : "full";
  std::string y = fmt::format(
      "# hapticd-eval rig: {} on the simulated {}\n"
      "server: {{rate_hz: 2000, clock: lockstep, seed: {}, shutdown_ramp_s: 0.05}}\n"
      "devices:\n"
      "  - name: dut\n"
      "    device:\n"
      "      plugin: sim\n"
      "      parameters:\n",
      spec.scheme.label, spec.device.name, spec.seed);
  // The rig's sim parameters, each left out where the run's own (--sim) sets its key: one value per key.
  std::vector<std::string> device_lines{fmt::format("urdf: {}", find_device_urdf(spec.device.name).string()),
                                        fmt::format("initial_position: [{:.17g}]", fmt::join(q0, ", "))};
  if (translational) device_lines.insert(device_lines.end(), {"passive_gimbal: true", "sensor_accelerations: true"});
  device_lines.insert(device_lines.end(), spec.attachment.begin(), spec.attachment.end());
  for (const std::string& line : device_lines)
    if (!has_key(spec.device.sim_parameters, line.substr(0, line.find(':')))) add_lines(y, {line}, "        ");
  add_lines(y, spec.device.sim_parameters, "        ");
  const bool admittance = spec.scheme.display == Scheme::Display::admittance;
  if (!spec.model_plugin.empty()) {
    y += fmt::format("    virtual_model:\n      plugin: {}\n      parameters:\n", spec.model_plugin);
    add_lines(y, spec.model, "        ");
  } else if (admittance || !spec.script.empty() || !spec.model.empty()) {
    const bool scripted = !spec.script.empty() || !admittance;
    y += "    virtual_model:\n";
    y += scripted ? "      plugin: scripted_wrench\n" : "      plugin: admittance\n";
    y += "      parameters:\n";
    if (admittance) {
      const double m = spec.scheme.virtual_mass_kg;
      if (!has_key(spec.model, "mass_kg")) y += fmt::format("        mass_kg: [{0:.17g}, {0:.17g}, {0:.17g}]\n", m);
      if (!has_key(spec.model, "damping_n_s_per_m")) y += "        damping_n_s_per_m: [0, 0, 0]\n";
      if (translational) {
        y += "        rotation: false\n";
      } else {
        y += "        rotation: true\n";
        if (!has_key(spec.model, "inertia_kg_m2")) y += "        inertia_kg_m2: [0.05, 0.05, 0.05]\n";
        if (!has_key(spec.model, "rotational_damping_n_m_s")) y += "        rotational_damping_n_m_s: [0, 0, 0]\n";
      }
      if (scripted) y += "        display: admittance\n";
    } else {
      y += "        display: impedance\n";
    }
    if (scripted && spec.script.empty()) y += "        signal: constant\n";  // force_n defaults to zero
    add_lines(y, spec.script, "        ");
    add_lines(y, spec.model, "        ");
  }
  if (spec.scheme.joint_space) {
    std::string parameters = preset.inverse_kinematics_takes_task ? "task: " + task : std::string();
    if (!parameters.empty() && !preset.inverse_kinematics_parameters.empty()) parameters += ", ";
    parameters += preset.inverse_kinematics_parameters;
    y += fmt::format("    inverse_kinematics:\n      plugin: {}\n      parameters: {{{}}}\n", preset.inverse_kinematics,
                     parameters);
  }
  std::string constant_inertia;
  if (spec.scheme.controller == "inverse_jacobian" && !preset.ijc_joint_inertia.empty()) {
    constant_inertia = fmt::format(", joint_inertia: [{}]", fmt::join(preset.ijc_joint_inertia, ", "));
  } else if (spec.scheme.controller == "transposed_jacobian" && !preset.tjc_task_mass.empty()) {
    constant_inertia = fmt::format(", task_mass: [{}]", fmt::join(preset.tjc_task_mass, ", "));
  }
  std::string friction;
  if (admittance && spec.device.friction_compensation && !preset.friction_file.empty()) {
    std::string tried;
    const auto file = find_config_file(preset.friction_file, &tried);
    if (!file) throw std::runtime_error("the friction file " + preset.friction_file + " is none of these:" + tried);
    friction = fmt::format(", friction_compensation: true, friction_file: {}", file->string());
  }
  y += fmt::format("    controller:\n      plugin: {}\n      parameters: {{{}{}{}{}}}\n", spec.scheme.controller,
                   spec.scheme.task_rows ? "task: " + task + ", " : std::string(), spec.scheme.controller_parameters,
                   constant_inertia, friction);
  // The thesis's experiments had no rate limit on the rendered force: a 10 N sine at 60 Hz changes at 3.8 kN/s.
  y += "    safety: {max_force_rate_n_per_s: 100000}\n";
  return y;
}

server::Session make_rig_session(const RigSpec& spec) {
  return server::Session::from_yaml(rig_yaml(spec), {}, fmt::format("<{} rig>", spec.scheme.id));
}

std::string run_rig(server::Session& session, std::uint64_t cycles,
                    const std::function<void(const RigSample&)>& sample) {
  RigSample s;
  for (std::uint64_t k = 0; k < cycles; ++k) {
    session.step(1);
    const server::DeviceView v = session.device("dut");
    if (!v.fault.empty()) return v.fault;
    s.t = v.time_s;
    s.commanded_force = v.task.wrench.force;
    s.measured_force = -v.operator_wrench.force;
    s.position = v.handle_pose.position;
    s.desired_position = v.task.pose.position;
    s.true_velocity = v.truth ? v.truth->handle_twist.linear : v.handle_twist.linear;
    s.true_angular_velocity = v.truth ? v.truth->handle_twist.angular : v.handle_twist.angular;
    s.true_force = v.truth ? v.truth->handle_wrench.force : v.operator_wrench.force;
    s.torque = v.command.torque_nm;
    sample(s);
  }
  return {};
}

}  // namespace hapticd::eval
