#pragma once
// A small JSON value for the evaluation reports: numbers, strings, booleans, null, arrays and objects (keys in
// insertion order), written with dump(). Non-finite numbers are written as null (JSON has no NaN).
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace hapticd::eval {

class Json {
 public:
  using Array = std::vector<Json>;
  using Object = std::vector<std::pair<std::string, Json>>;

  Json() = default;  // null
  Json(double v) : value_(v) {}
  Json(int v) : value_(static_cast<double>(v)) {}
  Json(long v) : value_(static_cast<double>(v)) {}
  Json(unsigned long v) : value_(static_cast<double>(v)) {}
  Json(bool v) : value_(v) {}
  Json(std::string v) : value_(std::move(v)) {}
  Json(const char* v) : value_(std::string(v)) {}
  Json(const std::vector<double>& v);

  static Json array() { return Json(Array{}); }
  static Json object() { return Json(Object{}); }

  // Appends to an array; sets a key of an object (replacing an existing one). Return *this for chaining.
  Json& push(Json v);
  Json& set(const std::string& key, Json v);

  // An array or object without elements (null counts as empty too).
  [[nodiscard]] bool empty() const noexcept;

  // indent 0: one line; otherwise that many spaces per level.
  [[nodiscard]] std::string dump(int indent = 0) const;

 private:
  explicit Json(Array a) : value_(std::move(a)) {}
  explicit Json(Object o) : value_(std::move(o)) {}
  void write(std::string& out, int indent, int level) const;
  std::variant<std::monostate, double, bool, std::string, Array, Object> value_;
};

}  // namespace hapticd::eval
