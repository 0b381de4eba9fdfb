#include "app/signals.hpp"

#include <csignal>

namespace hapticd::server {
namespace {
std::atomic<bool> g_stop_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the stop flag is set from a signal handler");

extern "C" void on_stop_signal(int) { g_stop_requested.store(true, std::memory_order_relaxed); }
}  // namespace

std::atomic<bool>& stop_flag() { return g_stop_requested; }

const std::atomic<bool>& install_stop_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // A file that reaches the file size limit (ulimit -f) fails its write (EFBIG, reported: the recording stops
  // whole) instead of killing the process with every device.
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGXFSZ, &ignore, nullptr);
  return g_stop_requested;
}

}  // namespace hapticd::server
