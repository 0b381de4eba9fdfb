// libFuzzer target: a teleoperation link's packets (hapticd_teleop) as a broken or hostile peer could send them:
// (even first byte) the bytes are the sample, every field arbitrary; (odd) a well-formed packet whose numbers are
// then taken from the bytes, which reaches the accepting paths. Whatever check_teleop_packet accepts goes into both
// sides of a link (master and remote, each architecture and passivity scheme, with and without rotation) for a few
// cycles: the force and torque each commands must stay finite and within the link's max_force and max_torque, the
// orientation it sends a unit quaternion, and the energies (translation's and rotation's) finite and never decreasing.
// A violation aborts.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/teleop_validation.hpp"
#include "hapticd/teleop/teleop_side.hpp"

namespace {

void require(bool condition) {
  if (!condition) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  hapticd_msg_TeleopPacket p{};
  if (data[0] % 2 == 1) {
    hapticd::dds::set_text(p.sender, "m");
    hapticd::dds::set_text(p.receiver, "r");
    p.role = data[0] / 2 % 2;
    p.serial = 1;
    double numbers[24] = {};
    std::memcpy(numbers, data + 1, std::min(size - 1, sizeof numbers));
    std::memcpy(p.position, numbers, sizeof p.position);
    std::memcpy(p.velocity, numbers + 3, sizeof p.velocity);
    std::memcpy(p.force, numbers + 6, sizeof p.force);
    std::memcpy(p.wave, numbers + 9, sizeof p.wave);
    p.energy_in = numbers[12];
    // Rotation: an orientation made unit from the bytes (when it can be), as a peer's would be.
    double n = 0.0;
    for (int i = 0; i < 4; ++i) n += numbers[13 + i] * numbers[13 + i];
    n = std::sqrt(n);
    for (int i = 0; i < 4; ++i)
      p.orientation[i] = std::isfinite(n) && n > 1e-6 ? numbers[13 + i] / n : (i == 0 ? 1.0 : 0.0);
    std::memcpy(p.angular_velocity, numbers + 17, sizeof p.angular_velocity);
    std::memcpy(p.torque, numbers + 20, sizeof p.torque);
    p.rotation_energy_in = numbers[23];
  } else {
    std::memcpy(&p, data + 1, std::min(size - 1, sizeof p));
  }
  if (!hapticd::dds::check_teleop_packet(p).empty()) return 0;
  using namespace hapticd::teleop;
  LinkSettings s;
  s.architecture = data[0] & 4 ? Architecture::position_position : Architecture::position_force;
  s.passivity = (data[0] >> 3) % 3 == 0 ? Passivity::none : Passivity::tdpa;
  if ((data[0] >> 3) % 3 == 2 && s.architecture == Architecture::position_force) s.passivity = Passivity::wave;
  s.rotation = (data[0] & 128) != 0 && s.passivity != Passivity::wave;
  for (const Role role : {Role::master, Role::remote}) {
    TeleopSide side(role, s);
    LinkPacket packet;
    packet.sequence = p.serial;
    packet.sent_ns = p.sent_ns;  // and the echo's times, as any peer may send them (the delay measurement's input)
    packet.has_echo = p.has_echo;
    packet.echo_sent_ns = p.echo_sent_ns;
    packet.echo_received_ns = p.echo_received_ns;
    packet.position = {p.position[0], p.position[1], p.position[2]};
    packet.velocity = {p.velocity[0], p.velocity[1], p.velocity[2]};
    packet.force = {p.force[0], p.force[1], p.force[2]};
    packet.wave = {p.wave[0], p.wave[1], p.wave[2]};
    packet.energy_in = p.energy_in;
    packet.orientation = Eigen::Quaterniond(p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3])
                             .normalized();  // as the link does
    packet.angular_velocity = {p.angular_velocity[0], p.angular_velocity[1], p.angular_velocity[2]};
    packet.torque = {p.torque[0], p.torque[1], p.torque[2]};
    packet.rotation_energy_in = p.rotation_energy_in;
    packet.stopped = p.stopped;
    LocalSample sample;
    sample.force = packet.force;  // the remote's environment, as extreme as a packet may be
    sample.torque = packet.torque;
    double in = 0.0, out = 0.0, turn_in = 0.0, turn_out = 0.0;
    for (int k = 0; k < 4; ++k) {
      side.receive(packet, sample.time_ns);
      ++packet.sequence;
      sample.time_ns += 1'000'000;
      sample.velocity = packet.velocity;
      sample.angular_velocity = packet.angular_velocity;
      const SideOutput o = side.cycle(sample, 1e-3);
      require(o.force.allFinite() && o.force.norm() <= s.max_force * (1 + 1e-9));
      require(o.torque.allFinite() && o.torque.norm() <= s.max_torque * (1 + 1e-9));
      require(o.packet.orientation.coeffs().allFinite() && std::abs(o.packet.orientation.norm() - 1.0) < 1e-6);
      require(o.packet.position.allFinite() && o.packet.wave.allFinite() && std::isfinite(o.packet.energy_in));
      const LinkClockFigures& clock = side.status().clock;
      require(std::isfinite(clock.round_trip_s) && std::isfinite(clock.offset_s) && clock.round_trip_s >= 0.0 &&
              std::isfinite(clock.mean_delay_in_s) && std::isfinite(clock.mean_delay_out_s));
      require(side.status().port->energy_in() >= in && side.status().port->energy_out() >= out);
      in = side.status().port->energy_in();
      out = side.status().port->energy_out();
      const EnergyPort& turn = *side.status().rotation_port;
      require(std::isfinite(turn.energy_in()) && turn.energy_in() >= turn_in && turn.energy_out() >= turn_out);
      turn_in = turn.energy_in();
      turn_out = turn.energy_out();
    }
  }
  return 0;
}
