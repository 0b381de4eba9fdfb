#include "hapticd/json_reader.hpp"

#include <cstdlib>
#include <cstring>

namespace hapticd {

JsonReader::Value JsonReader::Value::operator[](std::string_view key) const noexcept {
  if (!reader_ || node().kind != Kind::object) return {};
  for (std::uint32_t i = node().first; i != 0; i = reader_->nodes_[i].next)
    if (reader_->nodes_[i].key == key) return Value(reader_, i);
  return {};
}

JsonReader::Value JsonReader::Value::at(std::size_t n) const noexcept {
  if (!reader_ || node().kind != Kind::array) return {};
  std::uint32_t i = node().first;
  for (std::size_t k = 0; i != 0 && k < n; ++k) i = reader_->nodes_[i].next;
  return i != 0 ? Value(reader_, i) : Value();
}

JsonReader::Value JsonReader::Value::first() const noexcept {
  if (!reader_ || (node().kind != Kind::array && node().kind != Kind::object) || node().first == 0) return {};
  return Value(reader_, node().first);
}

JsonReader::Value JsonReader::Value::next() const noexcept {
  if (!reader_ || node().next == 0) return {};
  return Value(reader_, node().next);
}

std::optional<double> JsonReader::Value::number() const noexcept {
  if (!reader_ || node().kind != Kind::number) return std::nullopt;
  return node().number;
}
std::optional<bool> JsonReader::Value::boolean() const noexcept {
  if (!reader_ || node().kind != Kind::boolean) return std::nullopt;
  return node().boolean;
}
std::optional<std::string_view> JsonReader::Value::string() const noexcept {
  if (!reader_ || node().kind != Kind::string) return std::nullopt;
  return node().text;
}

std::optional<std::string_view> JsonReader::Value::source() const noexcept {
  if (!reader_ || (node().kind != Kind::object && node().kind != Kind::array)) return std::nullopt;
  return node().text;
}

bool JsonReader::fail(const char* why) noexcept {
  error_ = why;
  return false;
}

void JsonReader::skip_space() noexcept {
  while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\n' || text_[at_] == '\r' || text_[at_] == '\t'))
    ++at_;
}

bool JsonReader::parse(std::string_view text) noexcept {
  nodes_.clear();
  nodes_.emplace_back();  // index 0: none
  text_ = text;
  at_ = 0;
  ok_ = false;
  error_ = "";
  if (value(0) == 0) return false;
  skip_space();
  if (at_ != text_.size()) return fail("text after the value");
  ok_ = true;
  return true;
}

std::uint32_t JsonReader::value(int depth) noexcept {
  if (depth > 32) return fail("nested deeper than 32 levels"), 0;
  if (nodes_.size() > max_nodes_) return fail("more values than the reader holds"), 0;
  skip_space();
  if (at_ >= text_.size()) return fail("the text ends before a value"), 0;
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  const char c = text_[at_];
  if (c == '{' || c == '[') {
    const std::size_t begin = at_;
    // The container's source, once its closing bracket is read.
    const auto closed = [&] {
      ++at_;
      nodes_[index].text = text_.substr(begin, at_ - begin);
      return index;
    };
    const bool object = c == '{';
    nodes_[index].kind = object ? Kind::object : Kind::array;
    ++at_;
    skip_space();
    const char close = object ? '}' : ']';
    if (at_ < text_.size() && text_[at_] == close) return closed();
    std::uint32_t last = 0;
    for (;;) {
      std::string_view key;
      if (object) {
        skip_space();
        if (at_ >= text_.size() || text_[at_] != '"') return fail("expected a key"), 0;
        const std::size_t start = ++at_;
        while (at_ < text_.size() && text_[at_] != '"') at_ += text_[at_] == '\\' ? 2 : 1;
        if (at_ >= text_.size()) return fail("a key does not end"), 0;
        key = text_.substr(start, at_ - start);
        ++at_;
        skip_space();
        if (at_ >= text_.size() || text_[at_] != ':') return fail("expected ':'"), 0;
        ++at_;
      }
      const std::uint32_t child = value(depth + 1);
      if (child == 0) return 0;
      nodes_[child].key = key;
      if (last == 0)
        nodes_[index].first = child;
      else
        nodes_[last].next = child;
      last = child;
      ++nodes_[index].count;
      skip_space();
      if (at_ < text_.size() && text_[at_] == ',') {
        ++at_;
        continue;
      }
      if (at_ < text_.size() && text_[at_] == close) return closed();
      return fail(object ? "expected ',' or '}'" : "expected ',' or ']'"), 0;
    }
  }
  Node& n = nodes_[index];
  if (c == '"') {
    const std::size_t start = ++at_;
    while (at_ < text_.size() && text_[at_] != '"') at_ += text_[at_] == '\\' ? 2 : 1;
    if (at_ >= text_.size()) return fail("a string does not end"), 0;
    n.kind = Kind::string;
    n.text = text_.substr(start, at_ - start);
    ++at_;
    return index;
  }
  const auto word = [&](std::string_view w) { return text_.substr(at_, w.size()) == w; };
  if (word("true") || word("false")) {
    n.kind = Kind::boolean;
    n.boolean = c == 't';
    at_ += n.boolean ? 4 : 5;
    return index;
  }
  if (word("null")) {
    at_ += 4;
    return index;
  }
  // A number: strtod needs a terminated string; copy at most 63 characters of it.
  char digits[64];
  std::size_t len = 0;
  while (at_ + len < text_.size() && len < sizeof(digits) - 1 &&
         std::strchr("+-0123456789.eE", text_[at_ + len]) != nullptr)
    ++len;
  if (len == 0) return fail("not a JSON value"), 0;
  std::memcpy(digits, text_.data() + at_, len);
  digits[len] = '\0';
  char* end = nullptr;
  n.kind = Kind::number;
  n.number = std::strtod(digits, &end);
  if (end != digits + len) return fail("a malformed number"), 0;
  at_ += len;
  return index;
}

}  // namespace hapticd
