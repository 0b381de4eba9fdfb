#pragma once
#include <cstdint>

namespace hapticd {

// Result of a real-time call. By contract exceptions never cross update(), read() or write(); a plugin reports
// failure with error, and the server puts that plugin's device in its safe state. The interfaces do not declare
// those calls noexcept so that the server can catch an exception thrown despite the contract and treat it as
// an error of that device (an override declared noexcept that throws still ends the process: C++'s rule).
enum class ReturnCode : std::uint8_t { ok, error };

// Result of a device call: ok, or an error and why. The reason is static text (a string literal, or text that
// lives as long as the plugin object): real-time safe to return, and shown in the device's fault ("the
// device's read() failed: joint 2 over its speed limit").
struct Outcome {
  ReturnCode code = ReturnCode::ok;
  const char* reason = "";

  [[nodiscard]] static constexpr Outcome success() noexcept { return {}; }
  [[nodiscard]] static constexpr Outcome failure(const char* why) noexcept { return {ReturnCode::error, why}; }
  [[nodiscard]] constexpr bool ok() const noexcept { return code == ReturnCode::ok; }
};

}  // namespace hapticd
