#include "hapticd/demand.hpp"

#include <cstdio>
#include <cstdlib>

namespace hapticd::internal {

void demand_failed(const char* condition, const char* file, int line) noexcept {
  // No allocation, no logger: this may run on the loop thread, in any state.
  std::fprintf(stderr, "hapticd: internal invariant failed: %s (%s:%d); this is a bug, please report it\n", condition,
               file, line);
  std::fflush(stderr);
  std::abort();
}

}  // namespace hapticd::internal
