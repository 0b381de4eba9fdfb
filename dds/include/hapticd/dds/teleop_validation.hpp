#pragma once
// Checks of a teleoperation packet (hapticd_teleop) before a server's link takes it: well-formed names, a known
// role, a serial, finite numbers within bounds, a unit orientation, non-negative energies. A packet that fails is
// dropped and counted, never applied. A pure function, fuzzed with the engine commands' checks.
#include <string_view>

#include "hapticd_msg.h"

namespace hapticd::dds {

struct TeleopBounds {
  double max_position_m = 10.0;
  double max_speed_m_s = 50.0;
  double max_force_n = 10000.0;
  double max_wave = 1e4;
  double max_energy_j = 1e9;
  double max_angular_speed_rad_s = 500.0;
  double max_torque_n_m = 10000.0;
};

// Empty when the packet may be taken, else why not (a static text).
[[nodiscard]] std::string_view check_teleop_packet(const hapticd_msg_TeleopPacket& packet,
                                                   const TeleopBounds& bounds = {}) noexcept;

}  // namespace hapticd::dds
