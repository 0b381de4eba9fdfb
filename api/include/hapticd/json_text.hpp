#pragma once
// Writing JSON text by hand, without a document tree (the live view's messages, 30 a second per channel; the
// evaluation reports' strings): numbers in their shortest exact form (non-finite ones as null, which JSON has
// instead of NaN), strings escaped and valid UTF-8.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>

#include "hapticd/utf8.hpp"

namespace hapticd::json_text {

inline void append_number(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.append(buffer, result.ptr);
}

inline void append_integer(std::string& out, std::int64_t v) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.append(buffer, result.ptr);
}

// Escaped; bytes that are not valid UTF-8 written as U+FFFD (hapticd/utf8.hpp): a peer's bytes never make the
// text invalid for a JSON client.
inline void append_string(std::string& out, std::string_view text) {
  out += '"';
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t n = next_utf8(text, at);
    if (n != 1) {
      if (n == 0) {
        out += "\\ufffd";
        ++at;
      } else {
        out.append(text.substr(at, n));
        at += n;
      }
      continue;
    }
    const char c = text[at++];
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          static constexpr char kHex[] = "0123456789abcdef";
          out += "\\u00";
          out += kHex[(c >> 4) & 0xf];
          out += kHex[c & 0xf];
        } else {
          out += c;
        }
    }
  }
  out += '"';
}

// "key": (with the comma before it unless it is the first of its object).
inline void append_key(std::string& out, std::string_view key, bool first = false) {
  if (!first) out += ',';
  append_string(out, key);
  out += ':';
}

// A Foxglove time: {"sec":S,"nsec":N}.
inline void append_time(std::string& out, std::uint64_t ns) {
  out += "{\"sec\":";
  append_integer(out, static_cast<std::int64_t>(ns / 1000000000u));
  out += ",\"nsec\":";
  append_integer(out, static_cast<std::int64_t>(ns % 1000000000u));
  out += '}';
}

// An object of numbers, {"k1":v1,"k2":v2,...}, in the order given.
struct NumberField {
  std::string_view key;
  double value;
};
inline void append_number_object(std::string& out, std::initializer_list<NumberField> fields) {
  out += '{';
  bool first = true;
  for (const NumberField& f : fields) {
    append_key(out, f.key, first);
    append_number(out, f.value);
    first = false;
  }
  out += '}';
}

// {"x":..,"y":..,"z":..} and the same with "w" for a quaternion.
inline void append_vector3(std::string& out, double x, double y, double z) {
  append_number_object(out, {{"x", x}, {"y", y}, {"z", z}});
}
inline void append_quaternion(std::string& out, double x, double y, double z, double w) {
  append_number_object(out, {{"x", x}, {"y", y}, {"z", z}, {"w", w}});
}

}  // namespace hapticd::json_text
