#pragma once
// HAPTICD_DEMAND(condition): an invariant of the code, checked in every build (in the spirit of Drake's DEMAND).
// A false condition is a bug in hapticd (or a plugin), never bad input: bad input gets an error that names it
// (ConfigError, ParameterError, a refused request). On failure it prints the condition, file and line to stderr,
// calls the program's handler (set_demand_handler), if any, and aborts - no exception, so it may stand in
// real-time code; the cost of a check is its condition.
#include "hapticd/export.hpp"

namespace hapticd::internal {
[[noreturn]] HAPTICD_API void demand_failed(const char* condition, const char* file, int line) noexcept;

// What a program does with a broken invariant before the abort (hapticd: on a thread that is not a real-time
// loop, every device stops through its safe mode and the process exits with its code; docs/safety.md). Called
// with the message already printed; it need not return. Not called on a thread marked below.
using DemandHandler = void (*)(const char* condition, const char* file, int line) noexcept;
HAPTICD_API void set_demand_handler(DemandHandler handler) noexcept;
// The calling thread aborts at once on a broken invariant (a real-time loop: nothing else can stop its devices).
HAPTICD_API void abort_on_demand_failure_in_this_thread() noexcept;
}  // namespace hapticd::internal

#define HAPTICD_DEMAND(condition)                                         \
  do {                                                                    \
    if (!(condition)) [[unlikely]]                                        \
      ::hapticd::internal::demand_failed(#condition, __FILE__, __LINE__); \
  } while (false)
