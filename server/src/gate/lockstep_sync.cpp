#include "gate/lockstep_sync.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

namespace hapticd::server {

void LockstepSync::after_cycle(std::uint64_t index, const std::atomic<bool>& stopping) noexcept {
  using Clock = std::chrono::steady_clock;
  if (!settings_.lockstep_sync || index % snapshot_interval_ != 0) return;
  if (index == 0 && settings_.lockstep_start_wait_s > 0.0) {
    // Before the virtual clock runs away: wait for the engines to claim the devices and answer their first
    // states - on every device (each engine's first answer is to cycle 0: a run with several engines repeats),
    // or on any.
    const auto give_up = Clock::now() + std::chrono::duration<double>(settings_.lockstep_start_wait_s);
    const auto synced = [](const auto& d) { return d->synced.load(std::memory_order_acquire); };
    const auto ready = [&] {
      return settings_.lockstep_start_every ? std::all_of(devices_.begin(), devices_.end(), synced)
                                            : std::any_of(devices_.begin(), devices_.end(), synced);
    };
    while (!ready() && Clock::now() < give_up && !stopping.load(std::memory_order_acquire)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      nudge_(nudge_arg_);
    }
  }
  // Wait until each engine that answers every state has answered this one (bounded in wall time).
  const std::uint64_t serial = index / snapshot_interval_ + 1;
  for (auto& link : devices_) {
    DeviceGate& d = *link;
    if (!d.synced.load(std::memory_order_acquire)) continue;
    const auto give_up = Clock::now() + std::chrono::duration<double>(settings_.lockstep_wait_s);
    int spins = 0;
    while (d.answered.load(std::memory_order_acquire) < serial && d.synced.load(std::memory_order_acquire)) {
      if (++spins < 200) {
        std::this_thread::yield();
        continue;
      }
      if (Clock::now() > give_up) {
        d.synced.store(false, std::memory_order_release);  // stop waiting for it until it answers again
        timeouts_.fetch_add(1, std::memory_order_relaxed);
        break;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(20));
    }
  }
}

}  // namespace hapticd::server
