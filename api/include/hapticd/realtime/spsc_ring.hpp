#pragma once
// Single-producer single-consumer ring buffer: the loop pushes, one non-real-time thread pops. Lock-free,
// wait-free for both sides, storage allocated once at construction.
#include <atomic>
#include <cstddef>
#include <memory>
#include <new>

namespace hapticd::realtime {

template <class T>
class SpscRing {
 public:
  // capacity is rounded up to a power of two.
  explicit SpscRing(std::size_t capacity) {
    std::size_t c = 2;
    while (c < capacity) c *= 2;
    mask_ = c - 1;
    slots_ = std::make_unique<T[]>(c);
  }

  // Producer only. False when full.
  bool try_push(const T& value) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) > mask_) return false;
    slots_[head & mask_] = value;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  // Consumer only. False when empty.
  bool try_pop(T& out) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    out = slots_[tail & mask_];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  [[nodiscard]] std::size_t capacity() const noexcept { return mask_ + 1; }

 private:
  static constexpr std::size_t kLine = 64;
  alignas(kLine) std::atomic<std::size_t> head_{0};
  alignas(kLine) std::atomic<std::size_t> tail_{0};
  std::size_t mask_ = 0;
  std::unique_ptr<T[]> slots_;
};

}  // namespace hapticd::realtime
