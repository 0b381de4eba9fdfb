#pragma once
// A run-time request to one configured plugin, of any kind (hapticd/runtime_request.hpp): its own command, or a
// tunable parameter set. What the plugin throws becomes the refusal's text; an accepted set becomes the value in
// effect. Not real-time safe; the caller serializes the requests to one plugin.
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/parameters.hpp"
#include "hapticd/plugin.hpp"
#include "hapticd/runtime_request.hpp"
#include "loader/plugin_loader.hpp"

namespace hapticd::server {

// One configured plugin as its requests see it.
struct PluginRequestTarget {
  RuntimeRequests& plugin;
  const PluginDescriptor& descriptor;
  Parameters& parameters;  // the values in effect
};

template <class T>
PluginRequestTarget request_target(PluginInstance<T>& p) {
  return {*p.object, *p.descriptor, p.parameters};
}

// The plugin's own command (handle_request).
RuntimeReply send_command(const PluginRequestTarget& target, std::string_view name, const std::vector<double>& values);
// A tunable parameter's new value, already checked against the schema: the plugin's tune() gets every value in
// effect with it, and may refuse.
RuntimeReply tune_parameter(const PluginRequestTarget& target, const std::string& name, ParameterValue value);

// A plugin several devices share - their group's model - reached through the requests of each of them
// ("group_model.<name>"), one request at a time; none once it has been deactivated.
struct SharedPlugin {
  std::mutex requests;
  std::optional<PluginRequestTarget> target;  // guarded by `requests`; empty: none, or deactivated
};

}  // namespace hapticd::server
