#pragma once
// Between the data model's wire types (hapticd_msg.h) and the client library's value types (types.hpp).
// Private to the library: its users never see a wire type.
#include <string_view>

#include "hapticd/client/types.hpp"
#include "hapticd_msg.h"

namespace hapticd::client::wire {

[[nodiscard]] DeviceInfo from_msg(const hapticd_msg_DeviceDescription& in);
// No allocation: a state is converted on the receive thread for every sample.
void from_msg(const hapticd_msg_DeviceState& in, DeviceState& out) noexcept;
[[nodiscard]] GroupInfo from_msg(const hapticd_msg_GroupDescription& in);
void from_msg(const hapticd_msg_GroupState& in, GroupState& out) noexcept;
[[nodiscard]] Event from_msg(const hapticd_msg_Event& in);
[[nodiscard]] Telemetry from_msg(const hapticd_msg_Telemetry& in);
[[nodiscard]] FaultReport from_msg(const hapticd_msg_FaultReport& in);

// The command's wire form for a device (engine id and serial are the client's to fill).
void to_msg(const EngineCommand& in, std::string_view device, hapticd_msg_EngineCommand& out) noexcept;
[[nodiscard]] hapticd_msg_RequestKind to_msg(RequestKind kind) noexcept;

}  // namespace hapticd::client::wire
