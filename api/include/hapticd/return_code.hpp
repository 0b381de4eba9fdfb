#pragma once
#include <cstdint>

namespace hapticd {

// Result of a real-time call. By contract exceptions never cross update(), read() or write(); a plugin reports
// failure with error, and the server puts that plugin's device in its safe state. The interfaces do not declare
// those calls noexcept so that the server can catch an exception thrown despite the contract and treat it as
// an error of that device (an override declared noexcept that throws still ends the process: C++'s rule).
enum class ReturnCode : std::uint8_t { ok, error };

}  // namespace hapticd
