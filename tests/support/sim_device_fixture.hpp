#pragma once
// A simulated device configured in-process from YAML parameter text (as in a session file), stepped in
// lockstep by the test: the plugin class itself, so the tests can read its ground truth.
#include <yaml-cpp/yaml.h>

#include <string>

#include "config/yaml_reader.hpp"
#include "sim_device.hpp"
#include "support/test_paths.hpp"

namespace hapticd::test {

struct SimRig {
  explicit SimRig(const std::string& parameters_yaml, double rate_hz = 2000.0, std::uint64_t seed = 42) {
    const YAML::Node node = YAML::Load(parameters_yaml);
    const Parameters p =
        server::read_parameters(node, sim::SimDevice::parameter_schema(), "test.yaml", "parameters", 1);
    PluginContext context;
    context.device_name = "sim";
    context.rate_hz = rate_hz;
    context.seed = seed;
    context.config_directory = hapticd::test::source_dir() + "/config/sessions";
    device.configure(p, context);
    period_ns = static_cast<std::int64_t>(1e9 / rate_hz);
    state.joints.resize(device.description().dof());
    command.torque_nm.setZero(device.description().dof());
    (void)device.enable();
  }
  // One control cycle: read at the cycle's time, then write the current command.
  Outcome cycle() {
    CycleTime t;
    t.index = index;
    t.time_ns = static_cast<std::int64_t>(index) * period_ns;
    t.period_ns = period_ns;
    const Outcome r = device.read(t, state);
    (void)device.write(t, command);
    ++index;
    return r;
  }
  sim::SimDevice device;
  DeviceState state;
  JointCommand command;
  std::uint64_t index = 0;
  std::int64_t period_ns = 500000;
};

}  // namespace hapticd::test
