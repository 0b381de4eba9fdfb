#include "gate/peer.hpp"

namespace hapticd::server {

PeerId PeerId::socket(std::uint64_t connection) noexcept {
  PeerId id{DoorKind::socket, {}};
  for (std::size_t b = 0; b < 8; ++b) id.key[b] = static_cast<unsigned char>(connection >> (8 * b));
  return id;
}

std::uint64_t PeerId::connection() const noexcept {
  if (door != DoorKind::socket) return 0;
  std::uint64_t c = 0;
  for (std::size_t b = 0; b < 8; ++b) c |= static_cast<std::uint64_t>(key[b]) << (8 * b);
  return c;
}

std::string PeerId::text() const {
  switch (door) {
    case DoorKind::dds: {
      static constexpr char kHex[] = "0123456789abcdef";
      std::string s = "participant ";
      for (std::size_t i = 0; i < 12; ++i) {  // the GUID's prefix: host, process, participant
        s += kHex[key[i] >> 4];
        s += kHex[key[i] & 0xf];
      }
      return s;
    }
    case DoorKind::socket:
      return "connection " + std::to_string(connection());
    case DoorKind::link:
      return "the teleoperation link";
    case DoorKind::ros2:
      return "ROS 2";
    case DoorKind::none:
      break;
  }
  return "nobody";
}

}  // namespace hapticd::server
