#pragma once
// The C API's one error model (hapticd/client.h): a status code, and the calling thread's message for
// hapticd_last_error(); no exception crosses the interface.
#include <cmath>
#include <exception>
#include <new>
#include <string>
#include <string_view>

#include "hapticd/client.h"

namespace hapticd::client_c {

// Keeps `message` as the calling thread's last error and returns `status`.
hapticd_status fail(hapticd_status status, std::string_view message) noexcept;
[[nodiscard]] const char* last_error_text() noexcept;

// Runs f, turning any exception into a status (never across the C interface).
template <class F>
hapticd_status guarded(F&& f) noexcept {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    return fail(HAPTICD_ERROR_INTERNAL, "out of memory");
  } catch (const std::exception& e) {
    return fail(HAPTICD_ERROR_INTERNAL, e.what());
  } catch (...) {
    return fail(HAPTICD_ERROR_INTERNAL, "an unknown error");
  }
}

// A timeout argument: finite and >= 0.
[[nodiscard]] inline bool valid_timeout(double seconds) noexcept { return std::isfinite(seconds) && seconds >= 0.0; }

// A name argument: 1..31 characters. Empty view when it is not one (the caller fails with bad_name).
[[nodiscard]] std::string_view name_of(const char* text) noexcept;
hapticd_status bad_name(const char* what, const char* text) noexcept;

}  // namespace hapticd::client_c
