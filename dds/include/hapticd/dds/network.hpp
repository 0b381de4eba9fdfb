#pragma once
// Where the DDS interface talks (docs/deployment.md): by default the loopback interface only, multicast off,
// discovery by unicast to 127.0.0.1 (config/dds/cyclonedds-loopback.xml). For a lab network: the interfaces by
// name or address, unicast discovery peers, multicast optional - chosen by the session file (`dds.network`), by a
// program's options, or by the environment for every program at once:
//   HAPTICD_DDS_NETWORK="interfaces=eth1;peers=192.0.2.2,192.0.2.3;multicast=false"
//   HAPTICD_DDS_CONFIG=/path/to/cyclonedds.xml      (a whole Cyclone configuration; takes precedence)
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hapticd::dds {

struct NetworkSettings {
  std::vector<std::string> interfaces;  // names ("eth1") or addresses ("192.0.2.1"); at least one
  std::vector<std::string> peers;       // unicast discovery peers (addresses or host names)
  bool multicast = false;               // multicast discovery and data (else unicast only, to the peers)
};

inline constexpr const char* kNetworkVariable = "HAPTICD_DDS_NETWORK";
inline constexpr const char* kConfigVariable = "HAPTICD_DDS_CONFIG";

// Parses "interfaces=A,B;peers=C,D;multicast=true|false" (keys in any order; interfaces required). Throws
// std::invalid_argument naming the part it cannot take.
[[nodiscard]] NetworkSettings parse_network(std::string_view spec);
// Checks the settings: an interface, names and addresses of printable characters only (they go into XML).
// Throws std::invalid_argument naming the bad entry.
void validate(const NetworkSettings& settings);
// The Cyclone DDS configuration (XML text) for the settings.
[[nodiscard]] std::string cyclone_xml(const NetworkSettings& settings);
// "interfaces eth1; peers 192.0.2.2; multicast off", for logs.
[[nodiscard]] std::string describe(const NetworkSettings& settings);

}  // namespace hapticd::dds
