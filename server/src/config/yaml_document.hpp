#pragma once
// A session file's YAML as the readers may trust it: bounded before it is converted (at most kMaxYamlNodes
// values, aliases counted as often as they are used - a 4 MB list or an alias bomb is refused from the parser's
// events, before yaml-cpp builds a node of it; nested at most kMaxYamlDepth deep; no alias inside the value its
// anchor names, which would make the document a cycle), no mapping with the same key twice (an error naming both
// lines), and no node shared between two places (an alias is a copy, with its lines: an override through one path
// changes only that path).
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <string>

namespace hapticd::server {

inline constexpr std::size_t kMaxYamlNodes = 100000;
inline constexpr std::size_t kMaxYamlDepth = 64;

// Throws ConfigError (file, line, key path) for a syntax error, a document too large, or a duplicate key.
YAML::Node load_yaml_document(const std::string& text, const std::string& file);

}  // namespace hapticd::server
