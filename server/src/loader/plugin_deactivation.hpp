#pragma once
// Taking a plugin out of service without letting it stop the rest. deactivate() runs off the loop, when a scheme
// leaves it (a switch, a fault) and when the session stops; a plugin that throws there must not keep the other
// plugins from deactivating nor the devices from being disabled - a person may hold them.
#include <exception>
#include <string>
#include <string_view>

#include "loader/plugin_loader.hpp"

namespace hapticd::server {

// Calls the plugin's deactivate(); returns what it threw ("controller 'name': what"), empty if nothing.
template <class T>
std::string deactivate_plugin(PluginInstance<T>& plugin, std::string_view role) {
  if (!plugin.object) return {};
  const std::string who = std::string(role) + " '" + (plugin.descriptor ? plugin.descriptor->name : "?") + "'";
  try {
    plugin->deactivate();
  } catch (const std::exception& e) {
    return who + ": " + e.what();
  } catch (...) {
    return who + ": deactivate() threw an exception";
  }
  return {};
}

}  // namespace hapticd::server
