#pragma once
// Whether this test is built under a sanitizer, the same with GCC (which defines __SANITIZE_*__) and clang (which
// answers __has_feature): a sanitized build runs several times slower, and AddressSanitizer keeps freed memory in
// its quarantine, so timing watchdogs and resident-size checks are relaxed there.
#if defined(__has_feature)
#define HAPTICD_TEST_HAS_FEATURE(x) __has_feature(x)
#else
#define HAPTICD_TEST_HAS_FEATURE(x) 0
#endif

namespace hapticd::test {

#if defined(__SANITIZE_ADDRESS__) || HAPTICD_TEST_HAS_FEATURE(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#if defined(__SANITIZE_THREAD__) || HAPTICD_TEST_HAS_FEATURE(thread_sanitizer)
inline constexpr bool kThreadSanitizer = true;
#else
inline constexpr bool kThreadSanitizer = false;
#endif
inline constexpr bool kSanitized = kAddressSanitizer || kThreadSanitizer;

}  // namespace hapticd::test
