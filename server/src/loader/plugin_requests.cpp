#include "loader/plugin_requests.hpp"

#include <exception>
#include <utility>

namespace hapticd::server {

RuntimeReply send_command(const PluginRequestTarget& target, std::string_view name, const std::vector<double>& values) {
  const std::string failed = "'" + std::string(name) + "' failed in plugin '" + target.descriptor.name + "'";
  try {
    return target.plugin.handle_request(name, values);
  } catch (const std::exception& e) {
    return {false, failed + ": " + e.what()};
  } catch (...) {
    return {false, failed};
  }
}

RuntimeReply tune_parameter(const PluginRequestTarget& target, const std::string& name, ParameterValue value) {
  Parameters next = target.parameters;
  next.set(name, std::move(value), "run-time request");
  const std::string refused = "'" + name + "' refused by plugin '" + target.descriptor.name + "'";
  try {
    target.plugin.tune(next);
  } catch (const std::exception& e) {
    return {false, refused + ": " + e.what()};
  } catch (...) {
    return {false, refused};
  }
  target.parameters = std::move(next);
  return {true, name + " = " + format_value(target.parameters.value(name))};
}

}  // namespace hapticd::server
