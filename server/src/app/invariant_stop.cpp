#include "app/invariant_stop.hpp"

#include <spdlog/spdlog.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "app/commands.hpp"
#include "executor/executor.hpp"
#include "hapticd/demand.hpp"

namespace hapticd::server {
namespace {

std::atomic<bool>* g_stop = nullptr;
std::atomic<bool> g_failed{false};    // a thread took the failure on
std::atomic<bool> g_reported{false};  // and wrote g_what
std::array<char, 512> g_what{};

void on_broken_invariant(const char* condition, const char* file, int line) noexcept {
  if (g_stop == nullptr) return;  // not installed: abort
  if (g_failed.exchange(true, std::memory_order_acq_rel)) {
    // A second thread failing as well: the first one ends the process; this one only waits for it.
    for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
  }
  std::snprintf(g_what.data(), g_what.size(), "%s (%s:%d)", condition, file, line);
  g_reported.store(true, std::memory_order_release);
  g_stop->store(true, std::memory_order_release);  // every device through its safe mode, as on SIGTERM
  // The loops stop by themselves once their devices are at rest (damping, gravity hold and release: at most
  // the safety settings' safe_damping_s + safe_hold_s + safe_release_s; bounded here at 60 s). The thread
  // that runs the executor then ends the session and exits with code 4 itself; if it cannot (this thread held
  // something it needs), this one does, 5 s later.
  const auto start = std::chrono::steady_clock::now();
  while ((Executor::loops_running() > 0 || std::chrono::steady_clock::now() - start < std::chrono::milliseconds(50)) &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::seconds(5));
  std::fprintf(stderr,
               "hapticd: internal invariant failed: %s; every device was stopped through its safe mode; exit code %d\n",
               g_what.data(), kExitRuntimeError);
  std::fflush(stderr);
  std::_Exit(kExitRuntimeError);
}

}  // namespace

void install_invariant_stop(std::atomic<bool>& stop) {
  g_stop = &stop;
  internal::set_demand_handler(&on_broken_invariant);
}

std::optional<std::string> invariant_failure() {
  if (!g_reported.load(std::memory_order_acquire)) return std::nullopt;
  return std::string(g_what.data());
}

}  // namespace hapticd::server
