#pragma once
// HAPTICD_DEMAND(condition): an invariant of the code, checked in every build (in the spirit of Drake's DEMAND).
// A false condition is a bug in hapticd (or a plugin), never bad input: bad input gets an error that names it
// (ConfigError, ParameterError, a refused request). On failure it prints the condition, file and line to stderr
// and aborts - no exception, so it may stand in real-time code; the cost of a check is its condition.
#include "hapticd/export.hpp"

namespace hapticd::internal {
[[noreturn]] HAPTICD_API void demand_failed(const char* condition, const char* file, int line) noexcept;
}  // namespace hapticd::internal

#define HAPTICD_DEMAND(condition)                                         \
  do {                                                                    \
    if (!(condition)) [[unlikely]]                                        \
      ::hapticd::internal::demand_failed(#condition, __FILE__, __LINE__); \
  } while (false)
