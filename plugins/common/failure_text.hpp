#pragma once
// A vendor device plugin's failure text (real-time safe: fixed buffers, no allocation): the first reason a
// failure gives is kept - a later failure of the same episode says the same, so the fault names its cause - until
// a recovery (reset_fault) or an enable starts a new episode. The new episode writes into the other buffer, so a
// reason the server still holds (an Outcome points at it) is never overwritten while it may be read.
#include <array>
#include <cstddef>
#include <cstdio>

namespace hapticd::plugins {

template <std::size_t Size = 384>
class FailureText {
 public:
  // The episode's reason: `reason` if it is the first, else the first one.
  const char* keep(const char* reason) noexcept {
    std::array<char, Size>& text = buffers_[current_];
    if (text[0] == '\0') std::snprintf(text.data(), text.size(), "%s", reason);
    return text.data();
  }
  // The same, written by fill(char* text, std::size_t size) when the episode has no reason yet (a reason built in
  // parts: fill may write less than size and must terminate it).
  template <class Fill>
  const char* keep_with(Fill&& fill) noexcept {
    std::array<char, Size>& text = buffers_[current_];
    if (text[0] == '\0') fill(text.data(), text.size());
    return text.data();
  }
  // A recovery: the next failure says its own reason, in the other buffer.
  void new_episode() noexcept {
    current_ = 1 - current_;
    buffers_[current_][0] = '\0';
  }
  // An enable: the same, without leaving the buffer the last reason is in (nothing holds it any more).
  void clear() noexcept { buffers_[current_][0] = '\0'; }

 private:
  std::array<std::array<char, Size>, 2> buffers_{};
  std::size_t current_ = 0;
};

}  // namespace hapticd::plugins
