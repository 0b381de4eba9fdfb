#pragma once
// A device's mode and state flags (hapticd/state_flags.hpp: their one definition) from its snapshot.
#include <cstdint>

#include "hapticd/state_flags.hpp"
#include "session/device_snapshot.hpp"

namespace hapticd::server {

[[nodiscard]] inline DeviceMode device_mode(const DeviceSnapshot& s) noexcept {
  if (s.fault != DeviceFault::none) return DeviceMode::safe;
  if (s.stopping) return DeviceMode::stopping;
  return DeviceMode::running;
}

[[nodiscard]] inline std::uint32_t state_flags(const DeviceSnapshot& s) noexcept {
  using namespace state_flag;
  return (s.saturated ? torque_saturated : 0u) | (s.engine_weight > 0.0 && !s.engine_stale ? engine_active : 0u) |
         (s.engine_stale ? engine_stale : 0u) | (s.estop ? estop : 0u) | (s.fault != DeviceFault::none ? fault : 0u) |
         (s.switching ? switching : 0u) | (s.safe_damping ? safe_damping : 0u) |
         (s.limit_engaged ? limit_engaged : 0u) | (s.render_limited ? render_limited : 0u) |
         (s.thermal_derating ? thermal_derating : 0u) | (s.passivity_control ? passivity_control : 0u);
}

}  // namespace hapticd::server
