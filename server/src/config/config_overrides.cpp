#include "config/config_overrides.hpp"

#include <cstddef>

#include "config/config_error.hpp"

namespace hapticd::server {
namespace {

std::vector<std::string> split_keys(const std::string& path) {
  std::vector<std::string> keys;
  std::size_t start = 0;
  for (;;) {
    const std::size_t dot = path.find('.', start);
    keys.push_back(path.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (dot == std::string::npos) return keys;
    start = dot + 1;
  }
}

bool is_index(const std::string& key) {
  return !key.empty() && key.size() < 6 && key.find_first_not_of("0123456789") == std::string::npos;
}

}  // namespace

std::vector<AppliedOverride> apply_overrides(YAML::Node& root, const std::vector<std::string>& overrides) {
  std::vector<AppliedOverride> applied;
  for (const std::string& text : overrides) {
    const std::string where = "override '" + text + "'";
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0) throw ConfigError(where, 0, "", "expected <key.path>=<value>");
    const std::vector<std::string> keys = split_keys(text.substr(0, eq));
    YAML::Node value;
    try {
      value = YAML::Load(text.substr(eq + 1));
    } catch (const YAML::Exception& e) {
      throw ConfigError(where, 0, text.substr(0, eq), "the value is not YAML: " + e.msg);
    }
    if (!root.IsMap()) throw ConfigError(where, 0, "", "the session is not a mapping");
    YAML::Node node = root;
    std::string key_path;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const std::string& key = keys[i];
      if (key.empty()) throw ConfigError(where, 0, text.substr(0, eq), "an empty key");
      const bool last = i + 1 == keys.size();
      if (node.IsSequence()) {  // a device entry: by its name, or by its index
        std::size_t found = node.size();
        for (std::size_t k = 0; k < node.size(); ++k)
          if (node[k].IsMap() && node[k]["name"] && node[k]["name"].as<std::string>("") == key) found = k;
        if (found == node.size() && is_index(key)) found = std::stoul(key);
        if (found >= node.size())
          throw ConfigError(where, 0, key_path, "no entry named '" + key + "' (nor with that index)");
        key_path += "[" + std::to_string(found) + "]";
        if (last) {
          node[found] = value;
        } else {
          node.reset(node[found]);
        }
        continue;
      }
      if (!node.IsMap() && !node.IsNull())
        throw ConfigError(where, 0, key_path, "'" + key_path + "' is not a mapping: '" + key + "' cannot be set in it");
      key_path += (key_path.empty() ? "" : ".") + key;
      if (last) {
        node[key] = value;
      } else {
        if (!node[key]) node[key] = YAML::Node(YAML::NodeType::Map);
        YAML::Node next = node[key];
        node.reset(next);
      }
    }
    applied.push_back({text, key_path});
  }
  return applied;
}

void throw_if_overridden(const ConfigError& error, const std::vector<AppliedOverride>& applied) {
  for (auto o = applied.rbegin(); o != applied.rend(); ++o) {  // the last override of a key is the one in effect
    const std::string& k = o->key_path;
    const std::string& key = error.key();
    if (key == k || key.rfind(k + ".", 0) == 0 || key.rfind(k + "[", 0) == 0)
      throw ConfigError("override '" + o->text + "'", 0, key, error.message());
  }
}

}  // namespace hapticd::server
