#pragma once
// Plugin and server parameters as a schema: each parameter declares its type, default, bounds, unit and
// description once; the same declaration validates a configuration and documents it (hapticd
// --describe-plugin). The SDK knows no file format: the server reads YAML into ParameterValues and asks the
// schema to check them.
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "hapticd/export.hpp"

namespace hapticd {

enum class ParameterType : std::uint8_t { boolean, integer, real, string, real_vector };

[[nodiscard]] HAPTICD_API std::string_view to_string(ParameterType type) noexcept;

using ParameterValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

[[nodiscard]] HAPTICD_API std::string format_value(const ParameterValue& value);

// A bad parameter value. key() names the parameter; the server adds the file and line it came from.
class HAPTICD_API ParameterError : public std::runtime_error {
 public:
  ParameterError(std::string key, const std::string& message);
  ~ParameterError() override;
  [[nodiscard]] const std::string& key() const noexcept { return key_; }

 private:
  std::string key_;
};

struct ParameterSpec {
  std::string name;
  ParameterType type = ParameterType::real;
  std::string description;
  std::string unit;                             // empty for dimensionless
  std::optional<ParameterValue> default_value;  // absent: the parameter is required
  std::optional<double> minimum;                // numbers and every element of a vector
  std::optional<double> maximum;
  bool minimum_exclusive = false;
  std::optional<std::size_t> size;   // vectors: exact number of elements
  std::vector<std::string> choices;  // strings: the allowed values (empty: any)
  // May be set while the plugin runs (a set_parameter request): the server checks the value against this spec,
  // keeps the values in effect (answering get requests) and hands them to the plugin's tune(). Text parameters
  // are never tunable.
  bool tunable = false;
  // A number that can be turned off (a watchdog, a limit): a session file writes `off` (0 inside, within any
  // bound), while a written 0 is refused - turning a safety function off is said, never a side effect of a value.
  bool can_be_off = false;

  [[nodiscard]] bool required() const noexcept { return !default_value.has_value(); }
  // Throws ParameterError if the value breaks a bound, size or choice; the message says what would be valid.
  HAPTICD_API void check(const ParameterValue& value) const;
  // One line: type, unit, default, bounds. Used by the documentation printer.
  [[nodiscard]] HAPTICD_API std::string constraints_text() const;
};

class ParameterSchema;

// Fluent declaration of one parameter: schema.real("kp", "proportional gain").unit("N m/rad").minimum(0)...
class HAPTICD_API ParameterBuilder {
 public:
  ParameterBuilder(ParameterSchema& schema, std::size_t index) : schema_(schema), index_(index) {}
  ParameterBuilder& unit(std::string unit);
  ParameterBuilder& default_value(ParameterValue value);
  ParameterBuilder& minimum(double value);
  ParameterBuilder& greater_than(double value);
  ParameterBuilder& maximum(double value);
  ParameterBuilder& size(std::size_t elements);
  ParameterBuilder& choices(std::vector<std::string> allowed);
  // Settable at run time (ParameterSpec::tunable); the plugin implements tune().
  ParameterBuilder& tunable();
  // A number that `off` turns off (ParameterSpec::can_be_off).
  ParameterBuilder& can_be_off();

 private:
  ParameterSpec& spec();
  ParameterSchema& schema_;
  std::size_t index_;
};

class HAPTICD_API ParameterSchema {
 public:
  ParameterBuilder boolean(std::string name, std::string description);
  ParameterBuilder integer(std::string name, std::string description);
  ParameterBuilder real(std::string name, std::string description);
  ParameterBuilder string(std::string name, std::string description);
  ParameterBuilder real_vector(std::string name, std::string description);

  [[nodiscard]] const std::vector<ParameterSpec>& specs() const noexcept { return specs_; }
  [[nodiscard]] const ParameterSpec* find(std::string_view name) const noexcept;
  [[nodiscard]] std::vector<std::string> names() const;
  [[nodiscard]] std::vector<std::string> tunable_names() const;

 private:
  friend class ParameterBuilder;
  ParameterBuilder add(std::string name, ParameterType type, std::string description);
  std::vector<ParameterSpec> specs_;
};

// Validated parameter values handed to configure(). Every declared parameter is present (given or default);
// the typed getters throw ParameterError only on a programming error (a name or type the schema lacks).
class HAPTICD_API Parameters {
 public:
  void set(std::string name, ParameterValue value, std::string origin = {});

  [[nodiscard]] bool has(std::string_view name) const;
  [[nodiscard]] bool boolean(std::string_view name) const;
  [[nodiscard]] std::int64_t integer(std::string_view name) const;
  [[nodiscard]] double real(std::string_view name) const;
  [[nodiscard]] const std::string& string(std::string_view name) const;
  [[nodiscard]] const std::vector<double>& real_vector(std::string_view name) const;
  [[nodiscard]] const ParameterValue& value(std::string_view name) const;
  // Where the value came from ("file.yaml:12"), or empty for a default.
  [[nodiscard]] std::string origin(std::string_view name) const;

 private:
  struct Entry {
    ParameterValue value;
    std::string origin;
  };
  const Entry& entry(std::string_view name) const;
  std::map<std::string, Entry, std::less<>> values_;
};

}  // namespace hapticd
