#pragma once
// A small JSON reader for messages that come a thousand times a second (the Inverse Service's states, the engine
// socket's commands): parses a message into nodes that point into its text (no copies of strings), in storage
// reserved once, so a message allocates nothing. Bounded: a message deeper than 32 levels or with more nodes than the
// reader holds is refused. Strings are compared as written (keys and IDs with escapes do not match).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/export.hpp"

namespace hapticd {

class HAPTICD_API JsonReader {
 public:
  enum class Kind : std::uint8_t { null, boolean, number, string, array, object };
  struct Node {
    Kind kind = Kind::null;
    std::string_view key;   // in an object: the member's key
    std::string_view text;  // a string's characters (without quotes); an object's or array's JSON source
    double number = 0.0;
    bool boolean = false;
    std::uint32_t first = 0;  // array/object: index of the first child (0: none)
    std::uint32_t next = 0;   // the next sibling (0: none)
    std::uint32_t count = 0;  // array/object: children
  };

  // A value in the parsed message (or none: every lookup on it gives none again).
  class Value {
   public:
    Value() = default;
    Value(const JsonReader* reader, std::uint32_t index) : reader_(reader), index_(index) {}
    [[nodiscard]] explicit operator bool() const noexcept { return reader_ != nullptr; }
    [[nodiscard]] Kind kind() const noexcept { return reader_ ? node().kind : Kind::null; }
    [[nodiscard]] Value operator[](std::string_view key) const noexcept;  // an object's member
    [[nodiscard]] Value at(std::size_t i) const noexcept;                 // an array's element
    // An array's or object's first element, and an element's next sibling (none at the end): a walk through a
    // long array in one pass (at(i) walks from the first each time).
    [[nodiscard]] Value first() const noexcept;
    [[nodiscard]] Value next() const noexcept;
    [[nodiscard]] std::size_t size() const noexcept { return reader_ ? node().count : 0; }
    [[nodiscard]] std::optional<double> number() const noexcept;
    [[nodiscard]] std::optional<bool> boolean() const noexcept;
    [[nodiscard]] std::optional<std::string_view> string() const noexcept;
    // An object's or array's JSON source as it was in the text (to hand on whole); none for other kinds.
    [[nodiscard]] std::optional<std::string_view> source() const noexcept;
    [[nodiscard]] double number_or(double fallback) const noexcept { return number().value_or(fallback); }

   private:
    [[nodiscard]] const Node& node() const noexcept { return reader_->nodes_[index_]; }
    const JsonReader* reader_ = nullptr;
    std::uint32_t index_ = 0;
  };

  explicit JsonReader(std::size_t max_nodes = 4096) : max_nodes_(max_nodes) { nodes_.reserve(max_nodes + 1); }
  // Parses `text` (which must outlive the values); false with error() set when it is not one JSON value within
  // the bounds.
  bool parse(std::string_view text) noexcept;
  [[nodiscard]] Value root() const noexcept { return ok_ ? Value(this, 1) : Value(); }
  [[nodiscard]] const char* error() const noexcept { return error_; }

 private:
  std::uint32_t value(int depth) noexcept;  // 0: failed
  void skip_space() noexcept;
  bool fail(const char* why) noexcept;

  std::vector<Node> nodes_;  // [0] unused: index 0 means none
  std::size_t max_nodes_;
  std::string_view text_;
  std::size_t at_ = 0;
  bool ok_ = false;
  const char* error_ = "";
};

}  // namespace hapticd
