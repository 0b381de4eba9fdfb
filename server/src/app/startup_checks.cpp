#include "app/startup_checks.hpp"

#include <fmt/format.h>
#include <sys/mman.h>
#include <sys/resource.h>

namespace hapticd::server {

std::string check_address_space(int threads, std::size_t extra_bytes) {
  rlimit stack{};
  std::size_t stack_bytes = 8u << 20;
  if (getrlimit(RLIMIT_STACK, &stack) == 0 && stack.rlim_cur != RLIM_INFINITY && stack.rlim_cur > 0)
    stack_bytes = static_cast<std::size_t>(stack.rlim_cur);
  const std::size_t need = static_cast<std::size_t>(threads) * stack_bytes + extra_bytes;
  // A reservation without memory behind it counts against the address-space limit like a thread's stack does.
  void* p = mmap(nullptr, need, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (p != MAP_FAILED) {
    munmap(p, need);
    return {};
  }
  return fmt::format(
      "not enough address space left for the session's threads ({} MB more needed: {} threads at the "
      "stack size limit of {} MB, and working memory); raise the limit (ulimit -v) or lower the stack "
      "size (ulimit -s)",
      need >> 20, threads, stack_bytes >> 20);
}

}  // namespace hapticd::server
