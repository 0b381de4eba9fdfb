#pragma once
// Between the wire types (hapticd_msg.h) and the SDK's value types; bounded names and texts.
#include <Eigen/Core>
#include <cstdint>
#include <string_view>

#include "hapticd/spatial.hpp"
#include "hapticd/utf8.hpp"
#include "hapticd_msg.h"

namespace hapticd::dds {

// Copies `text` into a bounded char array (truncated, always NUL-terminated, the rest zeroed).
template <std::size_t N>
void set_text(char (&out)[N], std::string_view text) noexcept {
  const std::size_t n = text.size() < N - 1 ? text.size() : N - 1;
  for (std::size_t i = 0; i < N; ++i) out[i] = i < n ? text[i] : '\0';
}
// The text in a bounded char array, stopping at the first NUL or the end (never reads past it).
template <std::size_t N>
std::string_view text_of(const char (&in)[N]) noexcept {
  std::size_t n = 0;
  while (n < N && in[n] != '\0') ++n;
  return {in, n};
}
// True when the array holds a NUL (a well-formed bounded string).
template <std::size_t N>
bool terminated(const char (&in)[N]) noexcept {
  for (std::size_t i = 0; i < N; ++i)
    if (in[i] == '\0') return true;
  return false;
}

// True when the array holds a NUL and the text before it is valid UTF-8: a name or id a peer sent that the server
// may repeat to its JSON and Foxglove clients.
template <std::size_t N>
bool valid_text(const char (&in)[N]) noexcept {
  return terminated(in) && valid_utf8(text_of(in));
}

[[nodiscard]] Pose to_pose(const hapticd_msg_Pose& in) noexcept;
void to_msg(const Pose& in, hapticd_msg_Pose& out) noexcept;
[[nodiscard]] Eigen::Matrix<double, 6, 1> to_vector6(const double (&in)[6]) noexcept;
void to_msg(const Eigen::Matrix<double, 6, 1>& in, double (&out)[6]) noexcept;
void to_msg(const Wrench& in, double (&out)[6]) noexcept;
void to_msg(const Twist& in, double (&out)[6]) noexcept;

// The wall clock in ns since the epoch (DDS source timestamps).
[[nodiscard]] std::int64_t wall_clock_ns() noexcept;

}  // namespace hapticd::dds
