#pragma once
// UTF-8 as the JSON and Foxglove clients require it (RFC 3629: no overlong forms, no surrogates, nothing above
// U+10FFFF). Text from a peer - a DDS client's id, an engine's name, a device name in a packet - is checked with
// valid_utf8 where it is taken (a request with an id that is not UTF-8 is refused and counted), and every JSON
// string the server writes goes through next_utf8 (json_text::append_string): a byte that starts no valid
// sequence is written as U+FFFD, so no peer's bytes can make a client close its connection.
#include <cstddef>
#include <string_view>

namespace hapticd {

// The length of the valid UTF-8 sequence at text[at] (1-4), or 0 when the bytes there start none.
[[nodiscard]] constexpr std::size_t next_utf8(std::string_view text, std::size_t at) noexcept {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char b0 = byte(at);
  if (b0 < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xbf;  // the second byte's range
  if (b0 >= 0xc2 && b0 <= 0xdf) {
    n = 2;
  } else if (b0 >= 0xe0 && b0 <= 0xef) {
    n = 3;
    if (b0 == 0xe0) lo = 0xa0;  // overlong
    if (b0 == 0xed) hi = 0x9f;  // surrogates
  } else if (b0 >= 0xf0 && b0 <= 0xf4) {
    n = 4;
    if (b0 == 0xf0) lo = 0x90;  // overlong
    if (b0 == 0xf4) hi = 0x8f;  // above U+10FFFF
  } else {
    return 0;
  }
  if (at + n > text.size()) return 0;
  if (byte(at + 1) < lo || byte(at + 1) > hi) return 0;
  for (std::size_t i = 2; i < n; ++i)
    if (byte(at + i) < 0x80 || byte(at + i) > 0xbf) return 0;
  return n;
}

[[nodiscard]] constexpr bool valid_utf8(std::string_view text) noexcept {
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t n = next_utf8(text, at);
    if (n == 0) return false;
    at += n;
  }
  return true;
}

}  // namespace hapticd
