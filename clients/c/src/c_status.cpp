#include "c_status.hpp"

#include <cstring>

namespace hapticd::client_c {

namespace {
thread_local std::string last_error;
}  // namespace

hapticd_status fail(hapticd_status status, std::string_view message) noexcept {
  try {
    last_error.assign(message);
  } catch (...) {
    last_error.clear();  // no memory for the message: the status still says what
  }
  return status;
}

const char* last_error_text() noexcept { return last_error.c_str(); }

std::string_view name_of(const char* text) noexcept {
  if (text == nullptr) return {};
  const std::size_t n = strnlen(text, HAPTICD_NAME_SIZE);
  return n == 0 || n >= HAPTICD_NAME_SIZE ? std::string_view{} : std::string_view(text, n);
}

hapticd_status bad_name(const char* what, const char* text) noexcept {
  if (text == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, std::string(what) + " is NULL");
  return fail(HAPTICD_ERROR_INVALID_ARGUMENT, std::string(what) + " must have 1 to 31 characters");
}

}  // namespace hapticd::client_c
