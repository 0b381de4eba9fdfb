#pragma once
// Overrides of a session file, "path=value": the path is the keys from the top, separated by dots, a device
// entry named by its name (or its index) - "server.seed=7", "devices.v3.virtual_model.parameters.mass_kg=[2, 2, 2]";
// the value is YAML. Missing mapping keys are created; the result is validated like the file itself.
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

namespace hapticd::server {

// What an override changed, in the session reader's key notation ("devices[0].virtual_model.parameters.mass_kg"),
// so an error in an overridden value can name the override instead of a line of the file.
struct AppliedOverride {
  std::string text;      // as given
  std::string key_path;  // as the reader names it
};

class ConfigError;

// Applies the overrides to the parsed file, in order. Throws ConfigError (file "override '<text>'") when an
// override is malformed or names no device.
std::vector<AppliedOverride> apply_overrides(YAML::Node& root, const std::vector<std::string>& overrides);

// An error at a key an override set (or inside it) is the override's: throws it again naming the override (file
// "override '<text>'", no line); returns when no override set that key.
void throw_if_overridden(const ConfigError& error, const std::vector<AppliedOverride>& applied);

}  // namespace hapticd::server
