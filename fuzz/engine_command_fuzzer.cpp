// libFuzzer target: the DDS engine-command validation. Two ways to build a sample from the bytes: (even first
// byte) the bytes are the sample, as a broken or hostile writer could send it - every field arbitrary; (odd)
// a well-formed command whose kind, flag and numeric fields are then patched from the bytes (index, 8-byte
// value), which reaches the accepting paths. Whatever the validation accepts must turn into finite, bounded
// engine input with unit quaternions. A violation aborts (the finding).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "hapticd/dds/command_validation.hpp"
#include "hapticd/dds/conversion.hpp"

namespace {

void require(bool condition) {
  if (!condition) std::abort();
}

// A well-formed coupling command from engine "e" to device "d", then patched.
hapticd_msg_EngineCommand patched(const std::uint8_t* data, std::size_t size) {
  hapticd_msg_EngineCommand c{};
  hapticd::dds::set_text(c.device, "d");
  hapticd::dds::set_text(c.engine, "e");
  c.serial = 1;
  c.kind = static_cast<hapticd_msg_CommandKind>(data[0] / 2 % 3);
  c.local_model = (data[0] & 8) != 0;
  c.command_pose.orientation[0] = c.anchor.orientation[0] = 1.0;
  double* fields[] = {c.wrench,  c.anchor.position,       c.anchor.orientation,       c.stiffness,
                      c.damping, c.command_pose.position, c.command_pose.orientation, c.twist};
  const int lengths[] = {6, 3, 4, 6, 6, 3, 4, 6};
  for (std::size_t at = 1; at + 9 <= size; at += 9) {
    int index = data[at] % 38;
    double value = 0.0;
    std::memcpy(&value, data + at + 1, sizeof value);
    for (int f = 0; f < 8; ++f) {
      if (index < lengths[f]) {
        fields[f][index] = value;
        break;
      }
      index -= lengths[f];
    }
  }
  return c;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  hapticd_msg_EngineCommand c{};
  if (data[0] % 2 == 1) {
    c = patched(data, size);
  } else {
    std::memcpy(&c, data + 1, std::min(size - 1, sizeof c));
  }
  const hapticd::dds::CommandBounds b;
  if (!hapticd::dds::check_command_content(c, b).ok) return 0;
  const hapticd::EngineInput e = hapticd::dds::to_engine_input(c);
  require(e.wrench.force.allFinite() && e.wrench.torque.allFinite());
  require(e.wrench.force.norm() <= b.max_force_n);
  require(e.proxy_pose.position.allFinite() && e.motion_pose.position.allFinite());
  require(e.proxy_pose.position.norm() <= b.max_distance_m);
  if (e.has_proxy) require(std::abs(e.proxy_pose.orientation.norm() - 1.0) < 1e-9);
  require(e.stiffness.allFinite() && (e.stiffness.array() >= 0.0).all());
  return 0;
}
