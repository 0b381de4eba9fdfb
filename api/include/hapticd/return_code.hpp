#pragma once
#include <cstdint>

namespace hapticd {

// Result of a plugin's call: ok, or an error and why - every plugin kind answers with it (a device's read() and
// write(), a chain plugin's activate() and update(), a group model's). An error puts the plugin's device (a group
// model's: its group's devices) in its safe state, and the reason is shown in the fault ("virtual_model: the
// trajectory file ended"). The reason is static text (a string literal, or text that lives as long as the plugin
// object): real-time safe to return.
//
// The rule for exceptions (plugin.hpp checks it at compile time): the real-time methods do not throw, by contract,
// and are not declared noexcept - neither in the interfaces nor in a plugin's overrides - so that an exception
// thrown despite the contract is caught by the server and contained to that plugin's device (fault
// plugin_exception) instead of ending the process with every device it drives (C++ ends it when a noexcept
// function throws).
enum class ReturnCode : std::uint8_t { ok, error };

struct Outcome {
  ReturnCode code = ReturnCode::ok;
  const char* reason = "";

  [[nodiscard]] static constexpr Outcome success() noexcept { return {}; }
  [[nodiscard]] static constexpr Outcome failure(const char* why) noexcept { return {ReturnCode::error, why}; }
  [[nodiscard]] constexpr bool ok() const noexcept { return code == ReturnCode::ok; }
};

}  // namespace hapticd
