#pragma once
// The C API's structs from the C++ client library's values and back (hapticd/client.h). Fixed-size copies only:
// a state, a pose, a command are converted without touching the heap (the per-cycle calls rely on it).
#include <string_view>

#include "hapticd/client.h"
#include "hapticd/client/client.hpp"

namespace hapticd::client_c {

// Copies text into a fixed C buffer, cut to fit and always terminated.
template <std::size_t N>
void copy_text(char (&out)[N], std::string_view text) noexcept {
  const std::size_t n = text.size() < N - 1 ? text.size() : N - 1;
  for (std::size_t i = 0; i < n; ++i) out[i] = text[i];
  out[n] = '\0';
}

void to_c(const Pose& in, hapticd_pose& out) noexcept;
void to_c(const Twist& in, hapticd_twist& out) noexcept;
void to_c(const Wrench& in, hapticd_wrench& out) noexcept;
[[nodiscard]] Pose from_c(const hapticd_pose& in) noexcept;
[[nodiscard]] Twist from_c(const hapticd_twist& in) noexcept;
[[nodiscard]] Wrench from_c(const hapticd_wrench& in) noexcept;

void to_c(const client::DeviceState& in, hapticd_device_state& out) noexcept;
void to_c(const client::DeviceInfo& in, hapticd_device_info& out) noexcept;
void to_c(const client::GroupInfo& in, hapticd_group_info& out) noexcept;
void to_c(const client::GroupState& in, hapticd_group_state& out) noexcept;
void to_c(const client::Event& in, hapticd_event& out) noexcept;
void to_c(const client::Telemetry& in, hapticd_telemetry& out) noexcept;
void to_c(const client::FaultReport& in, hapticd_fault_report& out) noexcept;
void to_c(const client::Reply& in, hapticd_reply& out) noexcept;
void to_c(const ParameterInfo& in, hapticd_parameter_info& out) noexcept;
void to_c(const client::SceneObject& in, hapticd_scene_object& out) noexcept;
void to_c(const client::SceneContact& in, hapticd_scene_contact& out) noexcept;

// An engine command from its C form; false (and nothing written) for an unknown kind.
[[nodiscard]] bool from_c(const hapticd_command& in, client::EngineCommand& out) noexcept;

}  // namespace hapticd::client_c
