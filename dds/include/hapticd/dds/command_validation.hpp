#pragma once
// Checks of an engine command's content before the server may use it: well-formed, finite, within bounds.
// (Ownership, order and freshness need the server's state: server/src/gate/command_gate.) Pure functions,
// fuzzed by tests/unit/command_validation_fuzz_test.
#include <array>
#include <cstdint>
#include <string_view>

#include "hapticd/engine_input.hpp"
#include "hapticd_msg.h"

namespace hapticd::dds {

// Why a command was rejected; the index into Telemetry.rejected (the IDL lists the same order).
enum class RejectReason : std::uint8_t {
  malformed = 0,
  non_finite = 1,
  out_of_bounds = 2,
  out_of_order = 3,
  stale = 4,
  not_owner = 5,
  wrong_kind = 6,
  other = 7,
};
inline constexpr int kRejectReasons = 8;
[[nodiscard]] std::string_view to_string(RejectReason reason) noexcept;

struct CommandBounds {
  double max_force_n = 300.0;
  double max_torque_nm = 30.0;
  double max_stiffness_n_per_m = 20000.0;
  double max_rotational_stiffness_n_m_per_rad = 200.0;
  double max_damping_n_s_per_m = 500.0;
  double max_rotational_damping_n_m_s = 5.0;
  double max_distance_m = 2.0;                         // from the device's base ...
  std::array<double, 3> base_position{0.0, 0.0, 0.0};  // ... which stands here in the world frame
  double max_speed_m_s = 5.0;
  double max_angular_speed_rad_s = 20.0;
};

// Empty when the content is acceptable, else the first reason found.
struct ContentCheck {
  bool ok = false;
  RejectReason reason = RejectReason::other;
};
[[nodiscard]] ContentCheck check_command_content(const hapticd_msg_EngineCommand& command,
                                                 const CommandBounds& bounds) noexcept;

// The loop's view of a command that passed check_command_content (quaternions normalised).
[[nodiscard]] EngineInput to_engine_input(const hapticd_msg_EngineCommand& command) noexcept;

}  // namespace hapticd::dds
