#pragma once
// Real-time set-up of the loop, loudly: each step that is not permitted becomes a warning the caller logs.
#include <string>
#include <thread>
#include <vector>

namespace hapticd::server {

// mlockall(MCL_CURRENT | MCL_FUTURE). Returns a warning, or empty on success.
std::string lock_process_memory();

// The kernel's PM QoS CPU latency limit (/dev/cpu_dma_latency), held while this object lives: the kernel applies
// a written limit as long as the file stays open. At 0 the CPUs' idle loop polls instead of entering idle
// states with a long exit latency (in a VM, halting the virtual CPU), which is what cyclictest does by default.
class CpuLatencyLimit {
 public:
  CpuLatencyLimit() = default;
  ~CpuLatencyLimit();
  CpuLatencyLimit(const CpuLatencyLimit&) = delete;
  CpuLatencyLimit& operator=(const CpuLatencyLimit&) = delete;
  // Returns a warning, or empty on success.
  std::string hold(int microseconds);

 private:
  int fd_ = -1;
};
// SCHED_FIFO at `priority` (if > 0) and pinning to `cpu` (if >= 0) for the given thread. Returns warnings.
std::vector<std::string> make_thread_realtime(std::thread& thread, int priority, int cpu);
// Names the calling thread (at most 15 characters kept) for ps, top and the kernel's traces.
void name_this_thread(const std::string& name) noexcept;
// Timer slack of the calling thread to 1 ns (the default 50 us delays every wake-up of a normal thread).
void minimise_timer_slack() noexcept;
// Touch a stack region so that its pages are resident before the loop needs them (no page faults later).
void prefault_stack() noexcept;

}  // namespace hapticd::server
