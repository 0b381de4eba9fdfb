#include "json.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "hapticd/json_text.hpp"

namespace hapticd::eval {
namespace {

void write_string(std::string& out, const std::string& s) { json_text::append_string(out, s); }

}  // namespace

Json::Json(const std::vector<double>& v) : value_(Array{}) {
  for (double x : v) push(x);
}

Json& Json::push(Json v) {
  auto* a = std::get_if<Array>(&value_);
  if (a == nullptr) throw std::logic_error("Json::push on a value that is not an array");
  a->push_back(std::move(v));
  return *this;
}

Json& Json::set(const std::string& key, Json v) {
  auto* o = std::get_if<Object>(&value_);
  if (o == nullptr) throw std::logic_error("Json::set on a value that is not an object");
  for (auto& [k, existing] : *o) {
    if (k == key) {
      existing = std::move(v);
      return *this;
    }
  }
  o->emplace_back(key, std::move(v));
  return *this;
}

bool Json::empty() const noexcept {
  if (const Array* a = std::get_if<Array>(&value_)) return a->empty();
  if (const Object* o = std::get_if<Object>(&value_)) return o->empty();
  return std::holds_alternative<std::monostate>(value_);
}

std::string Json::dump(int indent) const {
  std::string out;
  write(out, indent, 0);
  return out;
}

void Json::write(std::string& out, int indent, int level) const {
  const auto newline = [&](int l) {
    if (indent > 0) out += '\n' + std::string(static_cast<std::size_t>(indent * l), ' ');
  };
  if (std::holds_alternative<std::monostate>(value_)) {
    out += "null";
  } else if (const double* d = std::get_if<double>(&value_)) {
    out += std::isfinite(*d) ? fmt::format("{:.10g}", *d) : "null";
  } else if (const bool* b = std::get_if<bool>(&value_)) {
    out += *b ? "true" : "false";
  } else if (const std::string* s = std::get_if<std::string>(&value_)) {
    write_string(out, *s);
  } else if (const Array* a = std::get_if<Array>(&value_)) {
    // Arrays of numbers stay on one line (series are long).
    bool flat = true;
    for (const Json& e : *a) flat = flat && (std::holds_alternative<double>(e.value_) || e.value_.index() == 0);
    out += '[';
    for (std::size_t i = 0; i < a->size(); ++i) {
      if (i > 0) out += flat || indent == 0 ? ", " : ",";
      if (!flat) newline(level + 1);
      (*a)[i].write(out, indent, level + 1);
    }
    if (!flat && !a->empty()) newline(level);
    out += ']';
  } else if (const Object* o = std::get_if<Object>(&value_)) {
    out += '{';
    for (std::size_t i = 0; i < o->size(); ++i) {
      if (i > 0) out += indent == 0 ? ", " : ",";
      newline(level + 1);
      write_string(out, (*o)[i].first);
      out += ": ";
      (*o)[i].second.write(out, indent, level + 1);
    }
    if (!o->empty()) newline(level);
    out += '}';
  }
}

}  // namespace hapticd::eval
