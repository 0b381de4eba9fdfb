#include "session/device_requests.hpp"

#include <cmath>
#include <optional>
#include <string_view>

#include "session/device_session.hpp"

namespace hapticd::server {
namespace {

using Stage = DeviceSession::Stage;

std::string in_quotes(std::string_view name) { return "'" + std::string(name) + "'"; }

// A run-time set of a parameter the plugin's schema declares obeys the schema's type, size and bounds, as the
// session file does; the message says what would be valid. Requests the schema does not name (operator.push,
// ...) are the plugin's to check.
std::optional<std::string> check_against_schema(const PluginDescriptor& plugin, std::string_view name,
                                                const std::vector<double>& values) {
  const ParameterSchema schema = plugin.parameter_schema();
  const ParameterSpec* spec = schema.find(name);
  if (spec == nullptr) return std::nullopt;
  ParameterValue value;
  switch (spec->type) {
    case ParameterType::real:
      if (values.size() != 1) return in_quotes(name) + " takes one number";
      value = values[0];
      break;
    case ParameterType::integer:
      if (values.size() != 1 || values[0] != std::floor(values[0]) || std::abs(values[0]) > 9.0e15)
        return in_quotes(name) + " takes one whole number";
      value = static_cast<std::int64_t>(values[0]);
      break;
    case ParameterType::boolean:
      if (values.size() != 1 || (values[0] != 0.0 && values[0] != 1.0)) return in_quotes(name) + " takes 0 or 1";
      value = values[0] == 1.0;
      break;
    case ParameterType::real_vector:
      value = values;
      break;
    case ParameterType::string:
      return in_quotes(name) + " is a text parameter: it cannot be set at run time";
  }
  for (double v : values)
    if (!std::isfinite(v)) return in_quotes(name) + ": values must be finite";
  try {
    spec->check(value);
  } catch (const ParameterError& e) {
    return in_quotes(name) + ": " + e.what();
  }
  return std::nullopt;
}

std::optional<Stage> stage_named(std::string_view stage) {
  if (stage == "device") return Stage::device;
  if (stage == "virtual_model") return Stage::virtual_model;
  if (stage == "controller") return Stage::controller;
  return std::nullopt;
}

RuntimeReply set_safety(DeviceSession& device, std::string_view name, const std::vector<double>& values) {
  if (name == "passivity_control") {
    if (values.size() != 1 || (values[0] != 0.0 && values[0] != 1.0)) return {false, "passivity_control takes 0 or 1"};
    device.request_passivity_control(values[0] == 1.0);
    return {true, values[0] == 1.0 ? "passivity controller on" : "passivity controller off"};
  }
  if (name == "recover") return device.request_recovery();  // the older spelling of a recover request
  return {false, "unknown safety parameter " + in_quotes(name) + " (passivity_control)"};
}

RuntimeReply plugin_request(DeviceSession& device, Stage stage, std::string_view stage_text, std::string_view name,
                            const std::vector<double>& values) {
  const PluginDescriptor* plugin = device.stage_plugin(stage);
  if (plugin == nullptr) {
    if (device.chain().schemes.empty()) return {false, "device '" + device.name() + "' has no running scheme"};
    return {false, "scheme '" + device.schemes().active_name() + "' has no " + std::string(stage_text)};
  }
  if (auto error = check_against_schema(*plugin, name, values)) return {false, *error};
  return device.plugin_request(stage, name, values);
}

RuntimeReply set_parameter(DeviceSession& device, std::string_view target, const std::vector<double>& values) {
  const auto dot = target.find('.');
  if (dot == std::string_view::npos) return {false, "expected <stage>.<parameter>, e.g. virtual_model.mass_kg"};
  const std::string_view stage_text = target.substr(0, dot);
  const std::string_view name = target.substr(dot + 1);
  if (stage_text == "safety") return set_safety(device, name, values);
  const std::optional<Stage> stage = stage_named(stage_text);
  if (!stage)
    return {false, "unknown stage " + in_quotes(stage_text) + " (device, virtual_model, controller or safety)"};
  return plugin_request(device, *stage, stage_text, name, values);
}

}  // namespace

RuntimeReply apply_request(DeviceSession& device, const DeviceRequest& request) {
  switch (request.kind) {
    case DeviceRequest::Kind::switch_scheme:
      if (!device.schemes().request(request.name)) return {false, "no scheme named " + in_quotes(request.name)};
      return {true, "switching to " + request.name};
    case DeviceRequest::Kind::set_parameter:
      return set_parameter(device, request.name, request.values);
    case DeviceRequest::Kind::drive_operator:
      return plugin_request(device, Stage::device, "device", "operator." + request.name, request.values);
    case DeviceRequest::Kind::emergency_stop:
      device.request_emergency_stop();
      return {true, "emergency stop"};
    case DeviceRequest::Kind::recover:
      return device.request_recovery();
  }
  return {false, "unknown request"};
}

}  // namespace hapticd::server
