#pragma once
// Strict reading of YAML: every mapping is read through a MappingReader that knows the keys it accepts, so an
// unknown key, a missing key or a value of the wrong type becomes a ConfigError with file, line and key path.
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "hapticd/parameters.hpp"

namespace hapticd::server {

// 1-based line of a node (0 if the node has no position).
int line_of(const YAML::Node& node);

// The closest candidate by edit distance, if it is close enough to be a likely typo; else empty.
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);

class MappingReader {
 public:
  // node must be a mapping whose keys are all in allowed_keys (an error otherwise, with a suggestion).
  // key_path names it in messages ("devices[0].controller").
  MappingReader(const YAML::Node& node, std::string key_path, std::string file, std::vector<std::string> allowed_keys);

  // The value of a key that must be present.
  YAML::Node required(const std::string& key);
  // The value of a key that may be absent (an undefined node then).
  YAML::Node optional(const std::string& key);
  // A scalar string value.
  std::string required_string(const std::string& key);
  [[nodiscard]] std::string path_of(const std::string& key) const;
  [[nodiscard]] const std::string& file() const noexcept { return file_; }
  [[nodiscard]] const YAML::Node& node() const noexcept { return node_; }

 private:
  YAML::Node node_;
  std::string key_path_;
  std::string file_;
};

// Reads a mapping of parameters against a schema: types converted as declared, bounds checked, defaults
// filled, unknown and missing keys reported. node may be undefined or null (all defaults).
// parent_line locates errors about missing keys when node itself is absent. Keys in `read_elsewhere` belong
// to the same mapping but are read by the caller.
Parameters read_parameters(const YAML::Node& node, const ParameterSchema& schema, const std::string& file,
                           const std::string& key_path, int parent_line,
                           const std::vector<std::string>& read_elsewhere = {});

}  // namespace hapticd::server
