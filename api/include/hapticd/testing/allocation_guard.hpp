#pragma once
// Proof of "no allocation in update()": counts heap allocations (malloc, calloc, realloc, aligned and
// posix_memalign, and so operator new and Eigen's allocator, which all end there) made by the calling thread
// while a guard is alive. Link hapticd::testing into the test executable; it interposes the malloc family.
//
//   hapticd::testing::AllocationGuard guard;
//   controller.update(cycle, input, command);
//   EXPECT_EQ(guard.allocations(), 0u);
//
// Under AddressSanitizer or ThreadSanitizer the sanitizer owns malloc: available() is false and tests skip
// the count (GTEST_SKIP) rather than pass without checking.
#include <cstddef>
#include <utility>

namespace hapticd::testing {

class AllocationGuard {
 public:
  AllocationGuard() noexcept;
  ~AllocationGuard();
  AllocationGuard(const AllocationGuard&) = delete;
  AllocationGuard& operator=(const AllocationGuard&) = delete;

  // Allocations on this thread since construction.
  [[nodiscard]] std::size_t allocations() const noexcept;
  [[nodiscard]] static bool available() noexcept;

 private:
  std::size_t start_;
};

// Allocations made by this thread while running f().
template <class F>
std::size_t count_allocations(F&& f) {
  AllocationGuard guard;
  std::forward<F>(f)();
  return guard.allocations();
}

}  // namespace hapticd::testing
