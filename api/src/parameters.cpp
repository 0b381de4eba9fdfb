#include "hapticd/parameters.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace hapticd {
namespace {

std::string number_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

bool is_number(ParameterType type) { return type == ParameterType::integer || type == ParameterType::real; }

void check_number(const ParameterSpec& spec, double v, const std::string& what) {
  if (!std::isfinite(v)) throw ParameterError(spec.name, what + " must be a finite number");
  if (spec.minimum) {
    if (spec.minimum_exclusive && !(v > *spec.minimum))
      throw ParameterError(spec.name,
                           what + " " + number_text(v) + " must be greater than " + number_text(*spec.minimum));
    if (!spec.minimum_exclusive && v < *spec.minimum)
      throw ParameterError(spec.name,
                           what + " " + number_text(v) + " is below the minimum " + number_text(*spec.minimum));
  }
  if (spec.maximum && v > *spec.maximum)
    throw ParameterError(spec.name,
                         what + " " + number_text(v) + " is above the maximum " + number_text(*spec.maximum));
}

}  // namespace

std::string_view to_string(ParameterType type) noexcept {
  switch (type) {
    case ParameterType::boolean:
      return "boolean";
    case ParameterType::integer:
      return "integer";
    case ParameterType::real:
      return "real";
    case ParameterType::string:
      return "string";
    case ParameterType::real_vector:
      return "list of reals";
  }
  return "unknown";
}

std::string format_value(const ParameterValue& value) {
  struct Formatter {
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(double d) const { return number_text(d); }
    std::string operator()(const std::string& s) const { return "\"" + s + "\""; }
    std::string operator()(const std::vector<double>& v) const {
      std::string out = "[";
      for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + number_text(v[i]);
      return out + "]";
    }
  };
  return std::visit(Formatter{}, value);
}

ParameterError::ParameterError(std::string key, const std::string& message)
    : std::runtime_error(message), key_(std::move(key)) {}
ParameterError::~ParameterError() = default;

void ParameterSpec::check(const ParameterValue& value) const {
  switch (type) {
    case ParameterType::integer:
      if (can_be_off && std::get<std::int64_t>(value) == 0) break;  // off
      check_number(*this, static_cast<double>(std::get<std::int64_t>(value)), "value");
      break;
    case ParameterType::real:
      if (can_be_off && std::get<double>(value) == 0.0) break;  // off
      check_number(*this, std::get<double>(value), "value");
      break;
    case ParameterType::real_vector: {
      const auto& v = std::get<std::vector<double>>(value);
      if (size && v.size() != *size)
        throw ParameterError(name, "expected " + std::to_string(*size) + " elements, got " + std::to_string(v.size()));
      for (std::size_t i = 0; i < v.size(); ++i) check_number(*this, v[i], "element " + std::to_string(i));
      break;
    }
    case ParameterType::string: {
      if (choices.empty()) break;
      const auto& s = std::get<std::string>(value);
      for (const auto& c : choices)
        if (c == s) return;
      std::string allowed;
      for (const auto& c : choices) allowed += (allowed.empty() ? "" : ", ") + c;
      throw ParameterError(name, "value \"" + s + "\" is not one of: " + allowed);
    }
    case ParameterType::boolean:
      break;
  }
}

std::string ParameterSpec::constraints_text() const {
  std::ostringstream out;
  out << to_string(type);
  if (size) out << " of " << *size;
  if (!unit.empty()) out << " [" << unit << "]";
  if (is_number(type) || type == ParameterType::real_vector) {
    if (minimum) out << (minimum_exclusive ? ", > " : ", >= ") << number_text(*minimum);
    if (maximum) out << ", <= " << number_text(*maximum);
    if (can_be_off) out << ", or off";
  }
  if (!choices.empty()) {
    out << ", one of:";
    for (const auto& c : choices) out << ' ' << c;
  }
  out << (default_value ? ", default " + format_value(*default_value) : std::string(", required"));
  if (tunable) out << ", tunable at run time";
  return out.str();
}

ParameterSpec& ParameterBuilder::spec() { return schema_.specs_[index_]; }
ParameterBuilder& ParameterBuilder::unit(std::string unit) {
  spec().unit = std::move(unit);
  return *this;
}
ParameterBuilder& ParameterBuilder::minimum(double value) {
  spec().minimum = value;
  spec().minimum_exclusive = false;
  return *this;
}
ParameterBuilder& ParameterBuilder::greater_than(double value) {
  spec().minimum = value;
  spec().minimum_exclusive = true;
  return *this;
}
ParameterBuilder& ParameterBuilder::maximum(double value) {
  spec().maximum = value;
  return *this;
}
ParameterBuilder& ParameterBuilder::size(std::size_t elements) {
  spec().size = elements;
  return *this;
}
ParameterBuilder& ParameterBuilder::choices(std::vector<std::string> allowed) {
  spec().choices = std::move(allowed);
  return *this;
}
ParameterBuilder& ParameterBuilder::tunable() {
  if (spec().type == ParameterType::string)
    throw std::logic_error("parameter '" + spec().name + "': a text parameter cannot be tunable");
  spec().tunable = true;
  return *this;
}
ParameterBuilder& ParameterBuilder::can_be_off() {
  if (spec().type != ParameterType::real && spec().type != ParameterType::integer)
    throw std::logic_error("parameter '" + spec().name + "': only a number can be turned off");
  spec().can_be_off = true;
  return *this;
}
ParameterBuilder& ParameterBuilder::default_value(ParameterValue value) {
  // An integer literal for a real parameter is a natural thing to write; store it as the declared type.
  if (spec().type == ParameterType::real && std::holds_alternative<std::int64_t>(value))
    value = static_cast<double>(std::get<std::int64_t>(value));
  spec().default_value = std::move(value);
  return *this;
}

ParameterBuilder ParameterSchema::add(std::string name, ParameterType type, std::string description) {
  ParameterSpec spec;
  spec.name = std::move(name);
  spec.type = type;
  spec.description = std::move(description);
  specs_.push_back(std::move(spec));
  return ParameterBuilder(*this, specs_.size() - 1);
}
ParameterBuilder ParameterSchema::boolean(std::string n, std::string d) {
  return add(std::move(n), ParameterType::boolean, std::move(d));
}
ParameterBuilder ParameterSchema::integer(std::string n, std::string d) {
  return add(std::move(n), ParameterType::integer, std::move(d));
}
ParameterBuilder ParameterSchema::real(std::string n, std::string d) {
  return add(std::move(n), ParameterType::real, std::move(d));
}
ParameterBuilder ParameterSchema::string(std::string n, std::string d) {
  return add(std::move(n), ParameterType::string, std::move(d));
}
ParameterBuilder ParameterSchema::real_vector(std::string n, std::string d) {
  return add(std::move(n), ParameterType::real_vector, std::move(d));
}

const ParameterSpec* ParameterSchema::find(std::string_view name) const noexcept {
  for (const auto& s : specs_)
    if (s.name == name) return &s;
  return nullptr;
}

std::vector<std::string> ParameterSchema::names() const {
  std::vector<std::string> out;
  out.reserve(specs_.size());
  for (const auto& s : specs_) out.push_back(s.name);
  return out;
}

std::vector<std::string> ParameterSchema::tunable_names() const {
  std::vector<std::string> out;
  for (const auto& s : specs_)
    if (s.tunable) out.push_back(s.name);
  return out;
}

void Parameters::set(std::string name, ParameterValue value, std::string origin) {
  values_[std::move(name)] = Entry{std::move(value), std::move(origin)};
}

bool Parameters::has(std::string_view name) const { return values_.find(name) != values_.end(); }

const Parameters::Entry& Parameters::entry(std::string_view name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw ParameterError(std::string(name), "parameter is not declared in the schema");
  return it->second;
}

template <class T>
static const T& typed(const ParameterValue& v, std::string_view name, const char* type) {
  if (const T* p = std::get_if<T>(&v)) return *p;
  throw ParameterError(std::string(name), std::string("parameter is not of type ") + type);
}

bool Parameters::boolean(std::string_view n) const { return typed<bool>(entry(n).value, n, "boolean"); }
std::int64_t Parameters::integer(std::string_view n) const { return typed<std::int64_t>(entry(n).value, n, "integer"); }
double Parameters::real(std::string_view n) const { return typed<double>(entry(n).value, n, "real"); }
const std::string& Parameters::string(std::string_view n) const {
  return typed<std::string>(entry(n).value, n, "string");
}
const std::vector<double>& Parameters::real_vector(std::string_view n) const {
  return typed<std::vector<double>>(entry(n).value, n, "list of reals");
}
const ParameterValue& Parameters::value(std::string_view n) const { return entry(n).value; }
std::string Parameters::origin(std::string_view n) const { return has(n) ? entry(n).origin : std::string(); }

}  // namespace hapticd
