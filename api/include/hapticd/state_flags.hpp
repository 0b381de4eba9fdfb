#pragma once
// A device's mode and state flags as hapticd reports them, one definition for every place that carries them: the
// DDS state and the fault reports' cycle records (the IDL's MODE_* and FLAG_* constants have the same values,
// checked at compile time by the server's bridge), the recording (its mode_names and flag_names attributes), the
// live view and the clients.
#include <array>
#include <cstdint>

namespace hapticd {

enum class DeviceMode : std::uint8_t { starting = 0, running = 1, stopping = 2, safe = 3, off = 4 };
inline constexpr std::array<const char*, 5> kDeviceModeNames = {"starting", "running", "stopping", "safe", "off"};

namespace state_flag {
inline constexpr std::uint32_t torque_saturated = 1u << 0;  // the command was clamped to the peak torque
inline constexpr std::uint32_t engine_active = 1u << 1;     // fresh engine input is being applied
inline constexpr std::uint32_t engine_stale = 1u << 2;      // the owner's commands missed the deadline
inline constexpr std::uint32_t estop = 1u << 3;
inline constexpr std::uint32_t fault = 1u << 4;
inline constexpr std::uint32_t switching = 1u << 5;           // a scheme switch ramp is running
inline constexpr std::uint32_t safe_damping = 1u << 6;        // safe mode (or stop), damping phase
inline constexpr std::uint32_t limit_engaged = 1u << 7;       // velocity damping or a workspace wall acted
inline constexpr std::uint32_t render_limited = 1u << 8;      // the rendered wrench was limited
inline constexpr std::uint32_t thermal_derating = 1u << 9;    // a joint's torque limit is below its peak
inline constexpr std::uint32_t passivity_control = 1u << 10;  // the passivity controller on the engine port is on
}  // namespace state_flag
// Bit i's name, the one spelling everywhere: hapticctl, the client libraries (C++ and Python), recordings (their
// flag_names attribute), the live view. The IDL's constant is FLAG_ and the name in capitals.
inline constexpr std::array<const char*, 11> kStateFlagNames = {
    "torque_saturated", "engine_active", "engine_stale",  "estop",          "fault",
    "switching",        "safe_damping",  "limit_engaged", "render_limited", "thermal_derating",
    "passivity_control"};

}  // namespace hapticd
