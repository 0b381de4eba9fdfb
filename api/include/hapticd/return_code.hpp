#pragma once
#include <cstdint>

namespace hapticd {

// Result of a real-time call. Exceptions never cross update(); a plugin reports failure with error, and the
// server puts that plugin's device in its safe state.
enum class ReturnCode : std::uint8_t { ok, error };

}  // namespace hapticd
