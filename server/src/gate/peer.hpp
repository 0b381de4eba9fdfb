#pragma once
// Who is on the other end of a door (docs/architecture.md, "The gate and its doors"): a peer is what a claim,
// an E-stop and a request's answer are bound to - a DDS participant (by its GUID, found from the writer that
// wrote a sample), an engine socket's connection (by its number), or the server's own teleoperation link. The
// door that knows the peer says which it is; the gate compares peers and never looks inside the key.
// A Sender is a peer and the channel a sample came through (a DDS writer; a connection is its own single channel):
// serial numbers are ordered per channel, and a claim ends when the channel that made it is gone.
#include <array>
#include <cstdint>
#include <string>

namespace hapticd::server {

enum class DoorKind : std::uint8_t { none = 0, dds = 1, socket = 2, link = 3, ros2 = 4 };
inline constexpr std::size_t kDoorKinds = 5;

struct PeerId {
  DoorKind door = DoorKind::none;
  std::array<unsigned char, 16> key{};  // a DDS participant's GUID; a connection's number; nothing for the link

  friend bool operator==(const PeerId&, const PeerId&) = default;
  [[nodiscard]] bool empty() const noexcept { return door == DoorKind::none; }
  // For messages: "participant 0110a4c3...", "connection 7", "the teleoperation link".
  [[nodiscard]] std::string text() const;

  static PeerId dds_participant(const std::array<unsigned char, 16>& guid) noexcept { return {DoorKind::dds, guid}; }
  static PeerId socket(std::uint64_t connection) noexcept;
  static PeerId link() noexcept { return {DoorKind::link, {}}; }
  static PeerId ros2() noexcept { return {DoorKind::ros2, {}}; }
  [[nodiscard]] bool is_socket() const noexcept { return door == DoorKind::socket; }
  [[nodiscard]] bool is_link() const noexcept { return door == DoorKind::link; }
  // A claim for the whole session (the teleoperation link's, ROS 2's): never ended by the claim checks.
  [[nodiscard]] bool holds_for_session() const noexcept { return door == DoorKind::link || door == DoorKind::ros2; }
  // The connection of a socket peer (0 for any other).
  [[nodiscard]] std::uint64_t connection() const noexcept;
};

struct Sender {
  PeerId peer;
  std::uint64_t channel = 0;  // a DDS writer's instance handle; 0 for a connection (its only channel)
};

}  // namespace hapticd::server
