#pragma once
#include <cstdint>

namespace hapticd::server {

// The clock the loop sleeps on. Real time: CLOCK_MONOTONIC with absolute-deadline sleeps. Lockstep: a virtual
// clock that jumps to each deadline at once, so a session runs as fast as the machine allows and its results
// do not depend on the machine's load.
class LoopClock {
 public:
  virtual ~LoopClock() = default;
  [[nodiscard]] virtual std::int64_t now_ns() noexcept = 0;
  virtual void sleep_until(std::int64_t deadline_ns) noexcept = 0;
  [[nodiscard]] virtual bool is_virtual() const noexcept = 0;
};

class MonotonicClock final : public LoopClock {
 public:
  std::int64_t now_ns() noexcept override;
  void sleep_until(std::int64_t deadline_ns) noexcept override;
  bool is_virtual() const noexcept override { return false; }
};

class VirtualClock final : public LoopClock {
 public:
  std::int64_t now_ns() noexcept override { return now_ns_; }
  void sleep_until(std::int64_t deadline_ns) noexcept override {
    if (deadline_ns > now_ns_) now_ns_ = deadline_ns;
  }
  bool is_virtual() const noexcept override { return true; }

 private:
  std::int64_t now_ns_ = 0;
};

// Monotonic time for measuring compute time, whichever clock the loop runs on.
std::int64_t monotonic_now_ns() noexcept;

}  // namespace hapticd::server
