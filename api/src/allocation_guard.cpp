// Counting interposer for the malloc family, for hapticd::testing::AllocationGuard.
// Defining malloc & co. in the test executable makes the dynamic linker bind every library's calls
// (libstdc++'s operator new, Eigen's aligned allocator, plugins) to these definitions; they count on the
// calling thread and forward to glibc's implementation.
#include "hapticd/testing/allocation_guard.hpp"

#include <cstddef>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define HAPTICD_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define HAPTICD_SANITIZED 1
#endif
#endif

namespace {
__attribute__((tls_model("initial-exec"))) thread_local std::size_t g_thread_allocations = 0;
}

#ifndef HAPTICD_SANITIZED
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);

void* malloc(std::size_t n) {
  ++g_thread_allocations;
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t size) {
  ++g_thread_allocations;
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t n) {
  ++g_thread_allocations;
  return __libc_realloc(p, n);
}
void* memalign(std::size_t alignment, std::size_t n) {
  ++g_thread_allocations;
  return __libc_memalign(alignment, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) {
  ++g_thread_allocations;
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  ++g_thread_allocations;
  void* p = __libc_memalign(alignment, n);
  if (p == nullptr && n != 0) return 12;  // ENOMEM
  *out = p;
  return 0;
}
void free(void* p) { __libc_free(p); }
}
#endif

namespace hapticd::testing {

AllocationGuard::AllocationGuard() noexcept : start_(g_thread_allocations) {}
AllocationGuard::~AllocationGuard() = default;
std::size_t AllocationGuard::allocations() const noexcept { return g_thread_allocations - start_; }

bool AllocationGuard::available() noexcept {
#ifdef HAPTICD_SANITIZED
  return false;
#else
  return true;
#endif
}

}  // namespace hapticd::testing
