#include "config/yaml_reader.hpp"

#include <algorithm>

#include "config/config_error.hpp"

namespace hapticd::server {
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string join(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : ", ") + w;
  return out.empty() ? "(none)" : out;
}

std::string unknown_key_message(const std::string& key, const std::vector<std::string>& valid) {
  std::string message = "unknown key '" + key + "'";
  const std::string guess = closest_match(key, valid);
  if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
  return message + "; valid keys: " + join(valid);
}

std::string scalar_text(const YAML::Node& node) {
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a mapping";
  return "nothing";
}

template <class T>
T convert_scalar(const YAML::Node& node, const std::string& file, const std::string& key, const char* expected) {
  if (!node.IsScalar())
    throw ConfigError(file, line_of(node), key, std::string("expected ") + expected + ", got " + scalar_text(node));
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    throw ConfigError(file, line_of(node), key, std::string("expected ") + expected + ", got " + scalar_text(node));
  }
}

ParameterValue convert(const YAML::Node& node, const ParameterSpec& spec, const std::string& file,
                       const std::string& key) {
  if (spec.can_be_off && node.IsScalar()) {
    // `off` says it; a 0 would turn a watchdog or a limit off without saying so.
    if (node.Scalar() == "off")
      return spec.type == ParameterType::integer ? ParameterValue{std::int64_t{0}} : ParameterValue{0.0};
    double number = 1.0;
    try {
      number = node.as<double>();
    } catch (const YAML::Exception&) {
    }
    if (number == 0.0)
      throw ConfigError(file, line_of(node), key,
                        "0 would turn it off: write 'off' to turn it off (" + spec.constraints_text() + ")");
  }
  switch (spec.type) {
    case ParameterType::boolean:
      return convert_scalar<bool>(node, file, key, "true or false");
    case ParameterType::integer:
      return convert_scalar<std::int64_t>(node, file, key, "an integer");
    case ParameterType::real: {
      // yaml-cpp reads "true" as a double of 1: a boolean where a number belongs is a mistake worth naming.
      if (node.IsScalar() && (node.Scalar() == "true" || node.Scalar() == "false"))
        throw ConfigError(file, line_of(node), key, "expected a real number, got " + scalar_text(node));
      return convert_scalar<double>(node, file, key, "a real number");
    }
    case ParameterType::string:
      return convert_scalar<std::string>(node, file, key, "a string");
    case ParameterType::real_vector: {
      if (!node.IsSequence())
        throw ConfigError(file, line_of(node), key, "expected a list of real numbers, got " + scalar_text(node));
      std::vector<double> values;
      for (std::size_t i = 0; i < node.size(); ++i)
        values.push_back(convert_scalar<double>(node[i], file, key + "[" + std::to_string(i) + "]", "a real number"));
      return values;
    }
  }
  throw ConfigError(file, line_of(node), key, "unsupported parameter type");
}

}  // namespace

int line_of(const YAML::Node& node) {
  if (!node.IsDefined()) return 0;
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : mark.line + 1;
}

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

namespace {
// A mapping key: a plain name (YAML allows lists and mappings as keys; a session file does not).
std::string key_of(const YAML::Node& key, const std::string& file, const std::string& key_path) {
  if (!key.IsScalar()) throw ConfigError(file, line_of(key), key_path, "expected a key name, got " + scalar_text(key));
  return key.Scalar();
}
}  // namespace

MappingReader::MappingReader(const YAML::Node& node, std::string key_path, std::string file,
                             std::vector<std::string> allowed_keys)
    : node_(node), key_path_(std::move(key_path)), file_(std::move(file)) {
  if (!node_.IsMap())
    throw ConfigError(file_, line_of(node_), key_path_, "expected a mapping of keys, got " + scalar_text(node_));
  for (const auto& entry : node_) {
    const std::string key = key_of(entry.first, file_, key_path_);
    if (std::find(allowed_keys.begin(), allowed_keys.end(), key) == allowed_keys.end())
      throw ConfigError(file_, line_of(entry.first), path_of(key), unknown_key_message(key, allowed_keys));
  }
}

std::string MappingReader::path_of(const std::string& key) const {
  return key_path_.empty() ? key : key_path_ + "." + key;
}

YAML::Node MappingReader::required(const std::string& key) {
  YAML::Node value = node_[key];
  if (!value.IsDefined() || value.IsNull())
    throw ConfigError(file_, line_of(node_), path_of(key), "missing required key '" + key + "'");
  return value;
}

YAML::Node MappingReader::optional(const std::string& key) { return node_[key]; }

std::string MappingReader::required_string(const std::string& key) {
  const YAML::Node value = required(key);
  return convert_scalar<std::string>(value, file_, path_of(key), "a string");
}

Parameters read_parameters(const YAML::Node& node, const ParameterSchema& schema, const std::string& file,
                           const std::string& key_path, int parent_line,
                           const std::vector<std::string>& read_elsewhere) {
  Parameters parameters;
  const bool present = node.IsDefined() && !node.IsNull();
  if (present && !node.IsMap())
    throw ConfigError(file, line_of(node), key_path, "expected a mapping of parameters, got " + scalar_text(node));

  if (present) {
    for (const auto& entry : node) {
      const std::string key = key_of(entry.first, file, key_path);
      if (std::find(read_elsewhere.begin(), read_elsewhere.end(), key) != read_elsewhere.end()) continue;
      const std::string path = key_path + "." + key;
      const ParameterSpec* spec = schema.find(key);
      if (spec == nullptr) {
        std::vector<std::string> valid = schema.names();
        valid.insert(valid.end(), read_elsewhere.begin(), read_elsewhere.end());
        throw ConfigError(file, line_of(entry.first), path, unknown_key_message(key, valid));
      }
      ParameterValue value = convert(entry.second, *spec, file, path);
      try {
        spec->check(value);
      } catch (const ParameterError& e) {
        throw ConfigError(file, line_of(entry.second), path, e.what());
      }
      parameters.set(key, std::move(value), file + ":" + std::to_string(line_of(entry.second)));
    }
  }
  for (const auto& spec : schema.specs()) {
    if (parameters.has(spec.name)) continue;
    if (spec.required())
      throw ConfigError(
          file, present ? line_of(node) : parent_line, key_path + "." + spec.name,
          "missing required parameter '" + spec.name + "' (" + spec.constraints_text() + ": " + spec.description + ")");
    parameters.set(spec.name, *spec.default_value);
  }
  return parameters;
}

}  // namespace hapticd::server
