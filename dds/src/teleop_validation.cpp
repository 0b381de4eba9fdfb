#include "hapticd/dds/teleop_validation.hpp"

#include <cmath>
#include <cstring>

#include "hapticd/dds/conversion.hpp"

namespace hapticd::dds {
namespace {

// Finite, with a Euclidean norm within `limit`.
bool bounded(const double (&v)[3], double limit) noexcept {
  for (const double x : v)
    if (!std::isfinite(x)) return false;
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) <= limit;
}

}  // namespace

std::string_view check_teleop_packet(const hapticd_msg_TeleopPacket& p, const TeleopBounds& b) noexcept {
  if (!valid_text(p.sender) || text_of(p.sender).empty()) return "the sender's name is malformed";
  if (!valid_text(p.receiver) || text_of(p.receiver).empty()) return "the receiver's name is malformed";
  if (p.role != hapticd_msg_TELEOP_MASTER && p.role != hapticd_msg_TELEOP_REMOTE) return "the role is unknown";
  // The bool is read as the byte it is: a sample from anywhere may hold any value there.
  unsigned char stopped = 0;
  std::memcpy(&stopped, &p.stopped, 1);
  if (stopped > 1) return "the stopped flag is neither 0 nor 1";
  unsigned char echo = 0;
  std::memcpy(&echo, &p.has_echo, 1);
  if (echo > 1) return "the echo flag is neither 0 nor 1";
  if (p.serial == 0) return "the serial is zero";
  if (!bounded(p.position, b.max_position_m)) return "the position is not finite or out of range";
  if (!bounded(p.velocity, b.max_speed_m_s)) return "the velocity is not finite or out of range";
  if (!bounded(p.force, b.max_force_n)) return "the force is not finite or out of range";
  if (!bounded(p.wave, b.max_wave)) return "the wave variable is not finite or out of range";
  if (!std::isfinite(p.energy_in) || p.energy_in < 0.0 || p.energy_in > b.max_energy_j)
    return "the energy is not finite, negative or out of range";
  double norm2 = 0.0;
  for (const double x : p.orientation) {
    if (!std::isfinite(x)) return "the orientation is not finite";
    norm2 += x * x;
  }
  if (std::abs(norm2 - 1.0) > 1e-3) return "the orientation is not a unit quaternion";
  if (!bounded(p.angular_velocity, b.max_angular_speed_rad_s))
    return "the angular velocity is not finite or out of range";
  if (!bounded(p.torque, b.max_torque_n_m)) return "the torque is not finite or out of range";
  if (!std::isfinite(p.rotation_energy_in) || p.rotation_energy_in < 0.0 || p.rotation_energy_in > b.max_energy_j)
    return "the rotation's energy is not finite, negative or out of range";
  return {};
}

}  // namespace hapticd::dds
