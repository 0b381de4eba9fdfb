#include "executor/loop_clock.hpp"

#include <cerrno>
#include <ctime>

namespace hapticd::server {

std::int64_t monotonic_now_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

std::int64_t MonotonicClock::now_ns() noexcept { return monotonic_now_ns(); }

void MonotonicClock::sleep_until(std::int64_t deadline_ns) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline_ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(deadline_ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

std::int64_t DeviceTickClock::now_ns() noexcept { return monotonic_now_ns(); }

void DeviceTickClock::sleep_until(std::int64_t deadline_ns) noexcept {
  // Between cycles the loop waits for ticks; a plain sleep (not used by the executor) waits for the time.
  MonotonicClock().sleep_until(deadline_ns);
}

std::int64_t DeviceTickClock::wait_for_cycle(std::int64_t deadline_ns, std::uint64_t& missed) noexcept {
  missed = 0;
  if (!started_) (void)device_.wait_for_tick(0);  // ticks from before the loop started are not its cycles
  const std::int64_t grace = !started_ ? first_tick_ns_ : free_running_ ? 0 : stall_ns_;
  const DeviceTick tick = device_.wait_for_tick(deadline_ns + grace);
  started_ = true;
  if (tick.count == 0) {  // none came: this cycle runs late (or, free-running, on time)
    free_running_ = true;
    return deadline_ns;
  }
  free_running_ = false;
  missed = tick.count - 1;
  return tick.time_ns;
}

}  // namespace hapticd::server
