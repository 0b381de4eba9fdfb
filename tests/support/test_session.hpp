#pragma once
// Builds device sessions from session-file text, with the test plugins on the search path.
#include <memory>
#include <string>
#include <vector>

#include "config/session_config.hpp"
#include "executor/executor.hpp"
#include "plugins/plugin_loader.hpp"
#include "session/device_session.hpp"

namespace hapticd::test {

struct TestSession {
  server::SessionConfig config;
  std::unique_ptr<server::PluginLoader> loader;
  std::vector<std::unique_ptr<server::DeviceSession>> devices;

  [[nodiscard]] std::vector<server::DeviceSession*> device_pointers() const;
  [[nodiscard]] server::ExecutorSettings executor_settings() const;
};

// yaml: a whole session file; the test plugin folder is added to server.plugin_paths.
TestSession build_test_session(const std::string& yaml);

// A device entry of the 1-DOF test chain (mass-spring, sine setpoint, axis IK, PD), with extra parameters.
std::string mass_spring_device_yaml(const std::string& name, const std::string& device_parameters = "",
                                    const std::string& controller_parameters = "");

}  // namespace hapticd::test
