#include "hapticd/realtime/tick_signal.hpp"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <ctime>

namespace hapticd::realtime {

static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t) &&
                  std::atomic<std::uint32_t>::is_always_lock_free,
              "a futex word is a plain 32-bit integer");

std::int64_t TickSignal::now_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

bool TickSignal::wait_while(const std::atomic<std::uint32_t>& word, std::uint32_t expected,
                            std::int64_t until_ns) noexcept {
  while (word.load(std::memory_order_acquire) == expected) {
    if (now_ns() >= until_ns) return false;
    timespec until{};
    until.tv_sec = static_cast<time_t>(until_ns / 1'000'000'000);
    until.tv_nsec = static_cast<long>(until_ns % 1'000'000'000);
    // An absolute CLOCK_MONOTONIC timeout (FUTEX_WAIT_BITSET); EAGAIN: the word changed already, EINTR: a signal.
    (void)syscall(SYS_futex, reinterpret_cast<const std::uint32_t*>(&word), FUTEX_WAIT_BITSET_PRIVATE, expected, &until,
                  nullptr, FUTEX_BITSET_MATCH_ANY);
  }
  return true;
}

void TickSignal::wake(std::atomic<std::uint32_t>& word) noexcept {
  (void)syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr, 0);
}

void TickSignal::tick(std::int64_t time_ns) noexcept {
  time_ns_.store(time_ns, std::memory_order_relaxed);
  sequence_.fetch_add(1, std::memory_order_release);
  wake(sequence_);
}

void TickSignal::tick() noexcept { tick(now_ns()); }

DeviceTick TickSignal::wait_for_tick(std::int64_t until_ns) noexcept {
  (void)wait_while(sequence_, seen_, until_ns);
  const std::uint32_t now = sequence_.load(std::memory_order_acquire);
  DeviceTick t;
  t.count = now - seen_;
  seen_ = now;
  if (t.count > 0) t.time_ns = time_ns_.load(std::memory_order_relaxed);
  return t;
}

}  // namespace hapticd::realtime
