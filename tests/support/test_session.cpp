#include "support/test_session.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "config/config_error.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "support/test_paths.hpp"

namespace hapticd::test {

std::size_t allocations_over_cycles(server::DeviceSession& device, std::uint64_t cycles, double torque_scale) {
  device.activate();
  device.cycle(cycle_at(0), torque_scale);
  testing::AllocationGuard guard;
  for (std::uint64_t k = 1; k <= cycles; ++k) device.cycle(cycle_at(k), torque_scale);
  return guard.allocations();
}

namespace {
std::string sim_vishard3_entry(const std::string& name) {
  return "  - name: " + name + R"(
    device:
      plugin: sim
      parameters:
        urdf: )" +
         hapticd::test::source_dir() + R"(/config/urdf/vishard3.urdf
        initial_position: [-0.3, 1.6, 0.0]
        passive_gimbal: true
)";
}
}  // namespace

std::string sim_vishard3_session_head(const std::string& name, std::uint64_t seed) {
  return "server: {clock: lockstep, seed: " + std::to_string(seed) + "}\ndevices:\n" + sim_vishard3_entry(name);
}

std::string vishard3_admittance_chain_yaml() {
  return R"(    virtual_model:
      plugin: admittance
      parameters: {mass_kg: [3.0, 3.0, 3.0], damping_n_s_per_m: [40.0, 40.0, 40.0], rotation: false}
    controller:
      plugin: resolved_acceleration
      parameters: {task: translation}
)";
}

std::string sim_vishard3_admittance_session(const std::string& name, std::uint64_t seed, const std::string& safety) {
  return sim_vishard3_session_head(name, seed) + "        attachment: operator\n" + vishard3_admittance_chain_yaml() +
         "    safety: {" + safety + "}\n";
}

std::string sim_vishard3_held_yaml(const std::string& name, const std::string& base) {
  return sim_vishard3_entry(name) +
         "        sensor_accelerations: true\n        attachment: operator\n    base_pose: " + base + "\n";
}

std::string sim_vishard3_device_yaml(const std::string& name, const std::string& force_profile,
                                     const std::string& force_n) {
  return sim_vishard3_entry(name) + R"(        attachment: wrench
        wrench_force: )" +
         force_profile + R"(
        wrench_force_n: )" +
         force_n + "\n";
}

std::string sim_wrench_step_device_yaml(const std::string& name, const std::string& model, const std::string& initial,
                                        const std::string& force_n, const std::string& torque_nm) {
  return "  - name: " + name + R"(
    device:
      plugin: sim
      parameters:
        urdf: )" +
         hapticd::test::source_dir() + R"(/config/urdf/)" + model + R"(.urdf
        initial_position: )" +
         initial + R"(
        attachment: wrench
        wrench_force: step
        wrench_force_n: )" +
         force_n + R"(
        wrench_force_start_s: 0.2
        wrench_torque: step
        wrench_torque_nm: )" +
         torque_nm + R"(
        wrench_torque_start_s: 0.2
)";
}

server::Session build_test_session(const std::string& yaml) {
  return server::Session::from_yaml(yaml, {{}, {hapticd::test::plugin_dir()}}, "session.yaml");
}

std::string config_error_of(const std::string& yaml) {
  try {
    (void)build_test_session(yaml);
    return "";
  } catch (const server::ConfigError& e) {
    return e.what();
  }
}

server::ExecutorResult run_session(server::Session& s, std::uint64_t at_cycle, const std::function<void()>& at) {
  const server::LoopPlan loops = s.impl().loop_plan();
  server::Executor executor(s.impl().executor_settings(), loops.loops());
  const std::atomic<bool> stop{false};
  bool done = !at;
  return executor.run(stop, [&] {
    if (!done && executor.live().cycles.load() >= at_cycle) {
      done = true;
      at();
    }
  });
}

std::string flow_mapping(const std::string& base, const std::string& overrides) {
  std::string extra = overrides;
  while (!extra.empty() && (extra.front() == ',' || extra.front() == ' ')) extra.erase(0, 1);
  // In order: base's keys, then new ones; a later entry (of base or the overrides) replaces an earlier one.
  std::vector<std::pair<std::string, YAML::Node>> entries;
  for (const std::string& text : {base, extra})
    for (const auto& e : YAML::Load("{" + text + "}")) {
      const std::string key = e.first.Scalar();
      const auto at = std::find_if(entries.begin(), entries.end(), [&](const auto& p) { return p.first == key; });
      if (at != entries.end())
        at->second = e.second;
      else
        entries.emplace_back(key, e.second);
    }
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << YAML::BeginMap;
  for (const auto& [key, value] : entries) out << YAML::Key << key << YAML::Value << value;
  out << YAML::EndMap;
  return out.c_str();
}

std::string mass_spring_device_yaml(const std::string& name, const std::string& device_parameters,
                                    const std::string& controller_parameters) {
  return "  - name: " + name +
         "\n"
         "    device:\n      plugin: test_mass_spring\n      parameters: " +
         flow_mapping("encoder_resolution_m: 1.0e-6", device_parameters) +
         "\n"
         "    virtual_model:\n      plugin: test_sine_setpoint\n      parameters: {amplitude_m: 0.05, frequency_hz: "
         "2}\n"
         "    inverse_kinematics:\n      plugin: test_axis_ik\n"
         "    controller:\n      plugin: test_pd\n      parameters: " +
         flow_mapping("kp: 400, kd: 20", controller_parameters) + "\n";
}

}  // namespace hapticd::test
