#include "hapticd/demand.hpp"

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace hapticd::internal {
namespace {
std::atomic<DemandHandler> g_handler{nullptr};
thread_local bool t_abort_here = false;
}  // namespace

void set_demand_handler(DemandHandler handler) noexcept { g_handler.store(handler, std::memory_order_release); }

void abort_on_demand_failure_in_this_thread() noexcept { t_abort_here = true; }

void demand_failed(const char* condition, const char* file, int line) noexcept {
  // No allocation, no logger: this may run on the loop thread, in any state.
  std::fprintf(stderr, "hapticd: internal invariant failed: %s (%s:%d); this is a bug, please report it\n", condition,
               file, line);
  std::fflush(stderr);
  if (!t_abort_here)
    if (DemandHandler handler = g_handler.load(std::memory_order_acquire)) handler(condition, file, line);
  std::abort();
}

}  // namespace hapticd::internal
