#include "session/device_requests.hpp"

#include <cmath>
#include <optional>
#include <string_view>
#include <variant>

#include "hapticd/demand.hpp"
#include "hapticd/parameter_info.hpp"

namespace hapticd::server {
namespace {

using Stage = DeviceRequests::Stage;

std::string in_quotes(std::string_view name) { return "'" + std::string(name) + "'"; }

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// A run-time value for a parameter of the schema, checked as the session file's would be (type, size, bounds);
// the message says what would be valid.
std::variant<ParameterValue, std::string> checked_value(const ParameterSpec& spec, const std::vector<double>& values) {
  const std::string name = in_quotes(spec.name);
  for (double v : values)
    if (!std::isfinite(v)) return name + ": values must be finite";
  ParameterValue value;
  switch (spec.type) {
    case ParameterType::real:
      if (values.size() != 1) return name + " takes one number";
      value = values[0];
      break;
    case ParameterType::integer:
      if (values.size() != 1 || values[0] != std::floor(values[0]) || std::abs(values[0]) > 9.0e15)
        return name + " takes one whole number";
      value = static_cast<std::int64_t>(values[0]);
      break;
    case ParameterType::boolean:
      if (values.size() != 1 || (values[0] != 0.0 && values[0] != 1.0)) return name + " takes 0 or 1";
      value = values[0] == 1.0;
      break;
    case ParameterType::real_vector:
      value = values;
      break;
    case ParameterType::string:
      return name + " is a text parameter: it cannot be set at run time";
  }
  try {
    spec.check(value);
  } catch (const ParameterError& e) {
    return name + ": " + e.what();
  }
  return value;
}

// A value as the numbers a reply carries (a boolean as 0 or 1; text carries none: it is in the message).
std::vector<double> numbers_of(const ParameterValue& value) {
  if (const auto* b = std::get_if<bool>(&value)) return {*b ? 1.0 : 0.0};
  if (const auto* i = std::get_if<std::int64_t>(&value)) return {static_cast<double>(*i)};
  if (const auto* r = std::get_if<double>(&value)) return {*r};
  if (const auto* v = std::get_if<std::vector<double>>(&value)) return *v;
  return {};
}

std::optional<Stage> stage_named(std::string_view stage) {
  if (stage == "device") return Stage::device;
  if (stage == "virtual_model") return Stage::virtual_model;
  if (stage == "inverse_kinematics") return Stage::inverse_kinematics;
  if (stage == "controller") return Stage::controller;
  if (stage == "group_model") return Stage::group_model;
  return std::nullopt;
}

// The stage's plugin, pinned to the scheme running now, or why there is none.
std::variant<DeviceRequests::StagePlugin, RuntimeReply> plugin_of(const DeviceRequests& device, Stage stage,
                                                                  std::string_view stage_text) {
  if (const auto plugin = device.stage_plugin(stage)) return *plugin;
  if (stage == Stage::group_model)
    return RuntimeReply{false, "device '" + device.name() + "' is in no group with a model"};
  if (device.chain().schemes.empty())
    return RuntimeReply{false, "device '" + device.name() + "' has no running scheme"};
  return RuntimeReply{false, "scheme '" + device.schemes().active_name() + "' has no " + std::string(stage_text)};
}

// "<stage>.<parameter>" split; the stage "safety" is the server's own.
struct Target {
  std::string_view stage;
  std::string_view name;
};
std::variant<Target, RuntimeReply> target_of(std::string_view target) {
  const auto dot = target.find('.');
  if (dot == std::string_view::npos)
    return RuntimeReply{false, "expected <stage>.<parameter>, e.g. virtual_model.mass_kg"};
  return Target{target.substr(0, dot), target.substr(dot + 1)};
}
RuntimeReply unknown_stage(std::string_view stage) {
  return {false, "unknown stage " + in_quotes(stage) +
                     " (device, virtual_model, inverse_kinematics, controller, group_model or safety)"};
}

RuntimeReply set_safety(DeviceRequests& device, std::string_view name, const std::vector<double>& values) {
  if (name == "passivity_control") {
    if (values.size() != 1 || (values[0] != 0.0 && values[0] != 1.0)) return {false, "passivity_control takes 0 or 1"};
    device.passivity_control(values[0] == 1.0);
    return {true, values[0] == 1.0 ? "passivity controller on" : "passivity controller off"};
  }
  if (name == "recover") return device.recover();  // the older spelling of a recover request
  return {false, "unknown safety parameter " + in_quotes(name) + " (passivity_control)"};
}

RuntimeReply plugin_command(DeviceRequests& device, Stage stage, std::string_view stage_text, std::string_view name,
                            const std::vector<double>& values) {
  const auto plugin = plugin_of(device, stage, stage_text);
  if (const auto* refused = std::get_if<RuntimeReply>(&plugin)) return *refused;
  return device.plugin_request(std::get<DeviceRequests::StagePlugin>(plugin), name, values);
}

// A parameter of one of the plugin stages ("<stage>.<parameter>", the stage not "safety"), or why there is none.
struct PluginParameter {
  DeviceRequests::StagePlugin stage;
  std::string_view name;
  const PluginDescriptor& plugin;
};
std::variant<PluginParameter, RuntimeReply> plugin_parameter(const DeviceRequests& device, std::string_view stage_text,
                                                             std::string_view name) {
  const std::optional<Stage> stage = stage_named(stage_text);
  if (!stage) return unknown_stage(stage_text);
  const auto plugin = plugin_of(device, *stage, stage_text);
  if (const auto* refused = std::get_if<RuntimeReply>(&plugin)) return *refused;
  const auto& pinned = std::get<DeviceRequests::StagePlugin>(plugin);
  return PluginParameter{pinned, name, *pinned.descriptor};
}

// A parameter the schema declares is set generically (tunable ones only); other names are the plugin's own
// commands (handle_request).
RuntimeReply set_parameter(DeviceRequests& device, std::string_view target_text, const std::vector<double>& values) {
  const auto target = target_of(target_text);
  if (const auto* refused = std::get_if<RuntimeReply>(&target)) return *refused;
  const auto [stage_text, name] = std::get<Target>(target);
  if (stage_text == "safety") return set_safety(device, name, values);
  const auto found = plugin_parameter(device, stage_text, name);
  if (const auto* refused = std::get_if<RuntimeReply>(&found)) return *refused;
  const PluginParameter& p = std::get<PluginParameter>(found);
  const ParameterSchema schema = p.plugin.parameter_schema();
  const ParameterSpec* spec = schema.find(name);
  if (spec == nullptr) return device.plugin_request(p.stage, name, values);
  if (!spec->tunable) {
    const std::vector<std::string> tunable = schema.tunable_names();
    return {false, in_quotes(name) + " of plugin '" + p.plugin.name + "' is not tunable at run time (" +
                       (tunable.empty() ? std::string("it has no tunable parameters") : "tunable: " + listed(tunable)) +
                       ")"};
  }
  auto value = checked_value(*spec, values);
  if (const auto* error = std::get_if<std::string>(&value)) return {false, *error};
  return device.tune(p.stage, spec->name, std::move(std::get<ParameterValue>(value)));
}

// Any parameter the schema declares, tunable or not: the value in effect.
RuntimeReply get_parameter(DeviceRequests& device, std::string_view target_text) {
  const auto target = target_of(target_text);
  if (const auto* refused = std::get_if<RuntimeReply>(&target)) return *refused;
  const auto [stage_text, name] = std::get<Target>(target);
  if (stage_text == "safety") {
    if (name != "passivity_control")
      return {false, "unknown safety parameter " + in_quotes(name) + " (passivity_control)"};
    const bool on = device.status().passivity_control();
    return {true, "passivity_control = " + std::string(on ? "true" : "false"), {on ? 1.0 : 0.0}};
  }
  const auto found = plugin_parameter(device, stage_text, name);
  if (const auto* refused = std::get_if<RuntimeReply>(&found)) return *refused;
  const PluginParameter& p = std::get<PluginParameter>(found);
  const ParameterSchema schema = p.plugin.parameter_schema();
  if (schema.find(name) == nullptr)
    return {false, "plugin '" + std::string(p.plugin.name) + "' has no parameter " + in_quotes(name) + " (" +
                       listed(schema.names()) + ")"};
  const std::optional<Parameters> parameters = device.stage_parameters(p.stage);
  if (!parameters) return {false, "plugin '" + std::string(p.plugin.name) + "' has been deactivated"};
  const ParameterValue& value = parameters->value(name);
  return {true, std::string(name) + " = " + format_value(value), numbers_of(value)};
}

// The server's own parameter of the safety stage, declared as a plugin's would be.
ParameterSpec passivity_control_spec() {
  ParameterSpec spec;
  spec.name = "passivity_control";
  spec.type = ParameterType::boolean;
  spec.description = "the passivity controller on the engine port (docs/safety.md)";
  spec.tunable = true;
  return spec;
}

// Every parameter a describe request can name, in its order: the device's, the running scheme's virtual model's,
// inverse kinematics' and controller's, the group model's, then the safety stage's.
struct Listed {
  std::string_view stage_text;
  std::optional<DeviceRequests::StagePlugin> stage;  // none: the safety stage
  ParameterSpec spec;
};
std::vector<Listed> listed_parameters(const DeviceRequests& device) {
  std::vector<Listed> out;
  for (const auto& [stage, text] : {std::pair{Stage::device, std::string_view("device")},
                                    std::pair{Stage::virtual_model, std::string_view("virtual_model")},
                                    std::pair{Stage::inverse_kinematics, std::string_view("inverse_kinematics")},
                                    std::pair{Stage::controller, std::string_view("controller")},
                                    std::pair{Stage::group_model, std::string_view("group_model")}}) {
    const auto plugin = device.stage_plugin(stage);
    if (!plugin) continue;
    const ParameterSchema schema = plugin->descriptor->parameter_schema();
    for (const ParameterSpec& spec : schema.specs()) out.push_back({text, plugin, spec});
  }
  out.push_back({"safety", std::nullopt, passivity_control_spec()});
  return out;
}

RuntimeReply describe(DeviceRequests& device, const Listed& p, std::size_t count) {
  ParameterInfo info;
  info.name = std::string(p.stage_text) + "." + p.spec.name;
  info.type = p.spec.type;
  info.unit = p.spec.unit;
  info.description = p.spec.description;
  info.tunable = p.spec.tunable;
  info.minimum = p.spec.minimum;
  info.maximum = p.spec.maximum;
  info.minimum_exclusive = p.spec.minimum_exclusive;
  ParameterValue value{device.status().passivity_control()};
  if (p.stage) {
    const std::optional<Parameters> parameters = device.stage_parameters(*p.stage);
    if (!parameters) return {false, "plugin '" + std::string(p.stage->descriptor->name) + "' has been deactivated"};
    value = parameters->value(p.spec.name);
  }
  info.value_text = format_value(value);
  info.value = numbers_of(value);
  return encode_parameter_info(info, count);
}

// A parameter's declaration and value in effect: by name ("<stage>.<parameter>"), or with no name the K-th of
// the device's list (values: {K}).
RuntimeReply describe_parameter(DeviceRequests& device, std::string_view target, const std::vector<double>& values) {
  const std::vector<Listed> listed = listed_parameters(device);
  if (target.empty()) {
    if (values.size() != 1 || !(values[0] >= 0.0) || values[0] != std::floor(values[0]))
      return {false, "name a parameter (<stage>.<parameter>), or give its index (0 to " +
                         std::to_string(listed.size() - 1) + ")"};
    if (values[0] >= static_cast<double>(listed.size()))
      return {false, "the device has " + std::to_string(listed.size()) + " parameters (indices 0 to " +
                         std::to_string(listed.size() - 1) + ")"};
    return describe(device, listed[static_cast<std::size_t>(values[0])], listed.size());
  }
  for (const Listed& p : listed)
    if (target == std::string(p.stage_text) + "." + p.spec.name) return describe(device, p, listed.size());
  // Not listed: get_parameter's refusal names what is wrong (the target, the stage or the parameter).
  const RuntimeReply refused = get_parameter(device, target);
  return refused.accepted ? RuntimeReply{false, "no parameter " + in_quotes(target)} : refused;
}

}  // namespace

std::optional<DeviceRequests::StagePlugin> DeviceRequests::stage_plugin(Stage stage) const {
  if (stage == Stage::device) return StagePlugin{stage, 0, chain_.device.descriptor};
  if (stage == Stage::group_model) {
    if (group_model_ == nullptr) return std::nullopt;
    std::lock_guard lock(group_model_->requests);
    if (!group_model_->target) return std::nullopt;
    return StagePlugin{stage, 0, &group_model_->target->descriptor};
  }
  if (chain_.schemes.empty()) return std::nullopt;
  const std::size_t index = schemes_.active_index();  // read once: the loop may switch right after
  const SchemeChain& scheme = chain_.schemes[index];
  if (stage == Stage::controller) return StagePlugin{stage, index, scheme.controller.descriptor};
  if (stage == Stage::inverse_kinematics) {
    if (!scheme.inverse_kinematics) return std::nullopt;
    return StagePlugin{stage, index, scheme.inverse_kinematics->descriptor};
  }
  if (!scheme.virtual_model) return std::nullopt;
  return StagePlugin{stage, index, scheme.virtual_model->descriptor};
}

template <class F>
auto DeviceRequests::with_stage_plugin(const StagePlugin& stage, F&& f)
    -> std::optional<std::invoke_result_t<F, const PluginRequestTarget&>> {
  if (stage.stage == Stage::group_model) {  // the group's: its own lock, shared by the group's devices
    std::lock_guard lock(group_model_->requests);
    if (!group_model_->target) return std::nullopt;  // deactivated since stage_plugin() found it
    return f(*group_model_->target);
  }
  std::lock_guard lock(plugin_requests_);
  if (stage.stage == Stage::device) return f(request_target(chain_.device));
  SchemeChain& scheme = chain_.schemes[stage.scheme];
  if (stage.stage == Stage::controller) return f(request_target(scheme.controller));
  // A scheme's stages are fixed at start-up: the one stage_plugin() found is there.
  if (stage.stage == Stage::inverse_kinematics) {
    HAPTICD_DEMAND(scheme.inverse_kinematics.has_value());
    return f(request_target(*scheme.inverse_kinematics));
  }
  HAPTICD_DEMAND(scheme.virtual_model.has_value());
  return f(request_target(*scheme.virtual_model));
}

namespace {
RuntimeReply gone() { return {false, "the group's model has been deactivated"}; }
}  // namespace

RuntimeReply DeviceRequests::plugin_request(const StagePlugin& stage, std::string_view name,
                                            const std::vector<double>& values) {
  return with_stage_plugin(stage, [&](const PluginRequestTarget& t) { return send_command(t, name, values); })
      .value_or(gone());
}

std::optional<Parameters> DeviceRequests::stage_parameters(const StagePlugin& stage) {
  return with_stage_plugin(stage, [](const PluginRequestTarget& t) { return t.parameters; });
}

RuntimeReply DeviceRequests::tune(const StagePlugin& stage, const std::string& name, ParameterValue value) {
  return with_stage_plugin(stage, [&](const PluginRequestTarget& t) { return tune_parameter(t, name, value); })
      .value_or(gone());
}

RuntimeReply DeviceRequests::recover() {
  const DeviceFault f = status_.fault();
  if (f == DeviceFault::none) return {false, "device '" + name_ + "' is not in its safe mode"};
  if (f == DeviceFault::configure)
    return {false,
            "device '" + name_ + "' never configured (" + chain_.configure_error + "); fix the session and restart"};
  if (f == DeviceFault::device_enable || f == DeviceFault::device_homing)
    return {false, "device '" + name_ + "' never ran: " + status_.fault_text() + "; fix the device and restart"};
  recovery_for_epoch_.store(stop_epoch_.load(std::memory_order_acquire) + 1, std::memory_order_release);
  return {true, "device '" + name_ + "' recovers once its safe mode has settled (unless it is stopped again first)"};
}

RuntimeReply DeviceRequests::apply(const DeviceRequest& request) {
  DeviceRequests& device = *this;
  switch (request.kind) {
    case DeviceRequest::Kind::switch_scheme:
      if (!device.switch_scheme(request.name)) {
        std::vector<std::string> names;
        for (const SchemeChain& sc : device.chain().schemes) names.push_back(sc.name);
        return {false, "no scheme named " + in_quotes(request.name) + " (schemes: " + listed(names) + ")"};
      }
      return {true, "switching to " + request.name};
    case DeviceRequest::Kind::set_parameter:
      return set_parameter(device, request.name, request.values);
    case DeviceRequest::Kind::get_parameter:
      return get_parameter(device, request.name);
    case DeviceRequest::Kind::describe_parameter:
      return describe_parameter(device, request.name, request.values);
    case DeviceRequest::Kind::drive_operator:
      return plugin_command(device, Stage::device, "device", "operator." + request.name, request.values);
    case DeviceRequest::Kind::emergency_stop:
      device.emergency_stop();
      return {true, "emergency stop"};
    case DeviceRequest::Kind::recover:
      return device.recover();
  }
  return {false, "unknown request"};
}

}  // namespace hapticd::server
