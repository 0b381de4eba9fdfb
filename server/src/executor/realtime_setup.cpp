#include "executor/realtime_setup.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

namespace hapticd::server {

std::string lock_process_memory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
    return std::string("cannot lock memory (mlockall: ") + std::strerror(errno) +
           "); page faults may delay the loop. Run as root or raise RLIMIT_MEMLOCK (ulimit -l).";
  return {};
}

std::vector<std::string> make_thread_realtime(std::thread& thread, int priority, int cpu) {
  std::vector<std::string> warnings;
  if (priority > 0) {
    sched_param param{};
    param.sched_priority = priority;
    if (const int rc = pthread_setschedparam(thread.native_handle(), SCHED_FIFO, &param); rc != 0)
      warnings.push_back(std::string("cannot switch the loop thread to SCHED_FIFO priority ") +
                         std::to_string(priority) + " (" + std::strerror(rc) +
                         "); it runs under the normal scheduler with more jitter. "
                         "Run as root, grant CAP_SYS_NICE or set an rtprio limit.");
  }
  if (cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (const int rc = pthread_setaffinity_np(thread.native_handle(), sizeof set, &set); rc != 0)
      warnings.push_back("cannot pin the loop thread to CPU " + std::to_string(cpu) + " (" + std::strerror(rc) + ")");
  }
  return warnings;
}

CpuLatencyLimit::~CpuLatencyLimit() {
  if (fd_ >= 0) close(fd_);
}

std::string CpuLatencyLimit::hold(int microseconds) {
  const int fd = open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
  if (fd < 0)
    return std::string("cannot hold the CPU latency limit (/dev/cpu_dma_latency: ") + std::strerror(errno) +
           "); idle CPUs may wake the loop late. Run as root, or set server.cpu_dma_latency_us: -1.";
  const std::int32_t value = microseconds;
  if (write(fd, &value, sizeof value) != static_cast<ssize_t>(sizeof value)) {
    const int error = errno;
    close(fd);
    return std::string("cannot set the CPU latency limit (/dev/cpu_dma_latency: ") + std::strerror(error) + ")";
  }
  fd_ = fd;
  return {};
}

void name_this_thread(const std::string& name) noexcept {
  prctl(PR_SET_NAME, name.substr(0, 15).c_str(), 0UL, 0UL, 0UL);
}

void minimise_timer_slack() noexcept { prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL); }

void prefault_stack() noexcept {
  constexpr std::size_t kBytes = 256 * 1024;
  unsigned char stack[kBytes];
  std::memset(stack, 0, kBytes);
  asm volatile("" : : "r"(stack) : "memory");  // keep the writes: the point is to touch the pages
}

}  // namespace hapticd::server
