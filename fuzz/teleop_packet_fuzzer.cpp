// libFuzzer target: a teleoperation link's packets (hapticd_teleop) as a broken or hostile peer could send them:
// (even first byte) the bytes are the sample, every field arbitrary; (odd) a well-formed packet whose numbers are
// then taken from the bytes, which reaches the accepting paths. Whatever check_teleop_packet accepts goes into both
// sides of a link (master and remote, each architecture and passivity scheme) for a few cycles: the force each commands
// must stay finite and within the link's max_force, and the energies finite and never decreasing. A violation aborts.
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
    double numbers[13] = {};
    std::memcpy(numbers, data + 1, std::min(size - 1, sizeof numbers));
    std::memcpy(p.position, numbers, sizeof p.position);
    std::memcpy(p.velocity, numbers + 3, sizeof p.velocity);
    std::memcpy(p.force, numbers + 6, sizeof p.force);
    std::memcpy(p.wave, numbers + 9, sizeof p.wave);
    p.energy_in = numbers[12];
  } else {
    std::memcpy(&p, data + 1, std::min(size - 1, sizeof p));
  }
  if (!hapticd::dds::check_teleop_packet(p).empty()) return 0;
  using namespace hapticd::teleop;
  LinkSettings s;
  s.architecture = data[0] & 4 ? Architecture::position_position : Architecture::position_force;
  s.passivity = (data[0] >> 3) % 3 == 0 ? Passivity::none : Passivity::tdpa;
  if ((data[0] >> 3) % 3 == 2 && s.architecture == Architecture::position_force) s.passivity = Passivity::wave;
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
    packet.stopped = p.stopped;
    LocalSample sample;
    sample.force = packet.force;  // the remote's environment, as extreme as a packet may be
    double in = 0.0, out = 0.0;
    for (int k = 0; k < 4; ++k) {
      side.receive(packet, sample.time_ns);
      ++packet.sequence;
      sample.time_ns += 1'000'000;
      sample.velocity = packet.velocity;
      const SideOutput o = side.cycle(sample, 1e-3);
      require(o.force.allFinite() && o.force.norm() <= s.max_force * (1 + 1e-9));
      require(o.packet.position.allFinite() && o.packet.wave.allFinite() && std::isfinite(o.packet.energy_in));
      const LinkClockFigures& clock = side.status().clock;
      require(std::isfinite(clock.round_trip_s) && std::isfinite(clock.offset_s) && clock.round_trip_s >= 0.0 &&
              std::isfinite(clock.mean_delay_in_s) && std::isfinite(clock.mean_delay_out_s));
      require(side.status().port->energy_in() >= in && side.status().port->energy_out() >= out);
      in = side.status().port->energy_in();
      out = side.status().port->energy_out();
    }
  }
  return 0;
}
