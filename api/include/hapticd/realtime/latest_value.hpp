#pragma once
// Lock-free hand-off of the latest value from one writer thread to one reader thread (a triple buffer):
// the writer never waits, the reader never waits and sees each published value at most once. T is copied,
// never allocated, so the reader side is real-time safe when T's copy is.
#include <array>
#include <atomic>
#include <cstdint>

namespace hapticd::realtime {

template <typename T>
class LatestValue {
 public:
  // Writer side (any one thread, not necessarily real-time).
  void publish(const T& value) {
    slots_[back_] = value;
    // Swap the back slot with the middle one and mark the middle as fresh.
    const std::uint8_t previous =
        middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = previous & kIndex;
  }
  // Reader side (one thread, real-time safe): true and `out` filled when a value was published since the
  // last successful take.
  bool take(T& out) noexcept {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const std::uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = previous & kIndex;
    out = slots_[front_];
    return true;
  }

 private:
  static constexpr std::uint8_t kFresh = 0x4;
  static constexpr std::uint8_t kIndex = 0x3;
  std::array<T, 3> slots_{};
  std::uint8_t back_ = 0;                // writer's
  std::uint8_t front_ = 1;               // reader's
  std::atomic<std::uint8_t> middle_{2};  // shared: index plus the fresh flag
};

}  // namespace hapticd::realtime
