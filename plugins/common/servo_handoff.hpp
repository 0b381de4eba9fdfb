#pragma once
// The hand-off between a device whose SDK or service owns the servo loop (OpenHaptics' scheduler callback, the
// I/O thread of Haply's service) and the server's loop, for the device plugins of such devices: the SDK's thread
// publishes each sample and ticks the device's clock; the loop takes the newest sample and hands over its force;
// the SDK's thread takes the force for its tick - on the device's clock (`server.clock: device`) it first waits for
// the loop's answer to that tick, at most `command_wait_us`, holds a late one for `hold_ticks` ticks, then applies
// zero. Lock-free both ways (triple buffers, a futex); Sample and Command are copied, never allocated.
#include <atomic>
#include <cstdint>

#include "hapticd/device_clock.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/realtime/latest_value.hpp"
#include "hapticd/realtime/tick_signal.hpp"

namespace hapticd::plugins {

template <class Sample, class Command>
class ServoHandoff {
 public:
  // The parameters every such plugin takes: command_wait_us, hold_ticks, max_sample_age_s.
  static void add_parameters(ParameterSchema& s) {
    s.real("command_wait_us",
           "on the device's clock: how long the device's thread waits for the loop's force of its tick; 0: 80 % of "
           "the period")
        .unit("us")
        .minimum(0.0)
        .maximum(10000.0)
        .default_value(0.0);
    s.integer("hold_ticks", "ticks a late force is held before zero is applied")
        .minimum(0)
        .maximum(10)
        .default_value(2);
    s.real("max_sample_age_s", "a sample older than this is a fault (the device's thread stopped)")
        .unit("s")
        .greater_than(0.0)
        .maximum(1.0)
        .default_value(0.05);
  }
  // configure(): the parameters above, for a loop at `rate_hz`.
  void configure(const Parameters& p, double rate_hz) {
    period_ns_ = static_cast<std::int64_t>(1e9 / rate_hz);
    const double wait_us = p.real("command_wait_us");
    command_wait_ns_ = wait_us > 0.0 ? static_cast<std::int64_t>(wait_us * 1e3) : period_ns_ * 8 / 10;
    hold_ticks_ = static_cast<int>(p.integer("hold_ticks"));
    max_sample_age_ns_ = static_cast<std::int64_t>(p.real("max_sample_age_s") * 1e9);
  }
  [[nodiscard]] DeviceClock* clock() noexcept { return &clock_; }
  [[nodiscard]] std::int64_t period_ns() const noexcept { return period_ns_; }
  [[nodiscard]] std::int64_t max_sample_age_ns() const noexcept { return max_sample_age_ns_; }
  // Any thread: the samples published so far.
  [[nodiscard]] std::uint64_t samples() const noexcept { return samples_made_.load(std::memory_order_acquire); }

  // The device's thread: a new sample (taken at `time_ns`, CLOCK_MONOTONIC) and a tick of the device's clock.
  void publish(const Sample& sample, std::int64_t time_ns) noexcept {
    samples_.publish(sample);
    samples_made_.fetch_add(1, std::memory_order_release);
    clock_.ticks.tick(time_ns);
  }
  // The device's thread, after publish(): the force to apply this tick (see above).
  void next_command(Command& applied) noexcept {
    const bool clocked = clock_.clocks_loop.load(std::memory_order_relaxed);
    if (clocked)
      (void)realtime::TickSignal::wait_while(command_count_, commands_seen_,
                                             realtime::TickSignal::now_ns() + command_wait_ns_);
    commands_seen_ = command_count_.load(std::memory_order_acquire);
    if (Command c; commands_.take(c)) {
      applied = c;
      missed_ = 0;
    } else if (clocked && ++missed_ > hold_ticks_) {
      applied = Command{};  // the loop is gone: no force
    }
  }
  // The loop: the newest sample since the last call (false: none came).
  bool take(Sample& sample) noexcept { return samples_.take(sample); }
  // The loop: its force for the device's thread.
  void command(const Command& c) noexcept {
    commands_.publish(c);
    command_count_.fetch_add(1, std::memory_order_release);
    // Only a thread that waits for the loop's force needs waking (on the device's clock): no system call else.
    if (clock_.clocks_loop.load(std::memory_order_relaxed)) realtime::TickSignal::wake(command_count_);
  }
  // enable(): forget the previous run's hand-off state (the device's thread is not running).
  void reset() noexcept { missed_ = 0; }

 private:
  // The device's ticks; knows whether the loop waits on them.
  class Clock final : public DeviceClock {
   public:
    DeviceTick wait_for_tick(std::int64_t until_ns) noexcept override {
      clocks_loop.store(true, std::memory_order_relaxed);
      return ticks.wait_for_tick(until_ns);
    }
    realtime::TickSignal ticks;
    std::atomic<bool> clocks_loop{false};
  };

  Clock clock_;
  realtime::LatestValue<Sample> samples_;
  realtime::LatestValue<Command> commands_;
  std::atomic<std::uint32_t> command_count_{0};  // futex word: the loop's forces so far
  std::atomic<std::uint64_t> samples_made_{0};
  std::uint32_t commands_seen_ = 0;  // the device's thread's
  int missed_ = 0;                   // the device's thread's
  std::int64_t period_ns_ = 1'000'000, command_wait_ns_ = 800'000, max_sample_age_ns_ = 50'000'000;
  int hold_ticks_ = 2;
};

}  // namespace hapticd::plugins
