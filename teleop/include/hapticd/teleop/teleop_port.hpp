#pragma once
// One side of a teleoperation link as a server runs it (docs/teleoperation.md, "Safety"): the control law and the
// passivity controller (TeleopSide) with the link's policies around them - the one place that decides
//   - when the device must stop: at the peer's stop (once per stop: this side may recover before the peer does),
//     and, for the remote, when the link has been silent for link_timeout_s (the master's force fades instead);
//   - where the link starts and goes on from: the handle at the first cycle, and after a recovery the handle as it
//     is (no pull towards where the peer went meanwhile);
//   - whether the link's force reaches the device: not while it is stopped or its session is ending.
// The server's TeleopLink carries the packets and carries out what a cycle decides (the E-stop, the reports); the
// evaluation suite runs the same port through its channel model. Real-time safe: no allocation, no exceptions
// after construction.
#include <Eigen/Core>
#include <cstdint>

#include "hapticd/teleop/teleop_side.hpp"

namespace hapticd::teleop {

// A stop the port decides for its device.
enum class PortStop { none, peer_stopped, link_lost };
// Its code in events and reports: "teleoperation_peer_stopped", "teleoperation_link_lost" ("" for none).
const char* stop_code(PortStop stop) noexcept;

struct PortCycle {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // for the device's handle
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // with rotation
  bool apply = false;              // hand `force` to the device (not while it is stopped or its session ends)
  LinkPacket packet;               // to send
  PortStop stop = PortStop::none;  // the device must stop now (its E-stop), and why
  // What changed this cycle, for the reports.
  bool lost = false;     // the link was lost (silent for link_timeout_s)
  bool back = false;     // packets again after a loss
  bool waiting = false;  // no packet yet after link_timeout_s: waiting for the peer
};

class TeleopPort {
 public:
  // Throws std::invalid_argument with link_settings_problem().
  TeleopPort(Role role, const LinkSettings& settings) : side_(role, settings) {}

  // A packet from the peer and its arrival on the clock of this side's samples.
  void receive(const LinkPacket& packet, std::int64_t arrival_ns) noexcept { side_.receive(packet, arrival_ns); }
  // The packets come from another sender from now on (TeleopSide::peer_changed).
  void peer_changed() noexcept { side_.peer_changed(); }
  // One cycle of dt seconds: `stopped`, the device is in its safe state (a fault, an E-stop); `ending`, its session
  // is ending (the shutdown ramp: no force, no stop - the peer's link times out).
  PortCycle cycle(const LocalSample& sample, double dt, bool stopped, bool ending) noexcept;

  [[nodiscard]] const SideStatus& status() const noexcept { return side_.status(); }

 private:
  TeleopSide side_;
  bool started_ = false;
  bool was_stopped_ = false;
  bool peer_stop_seen_ = false;
  bool lost_reported_ = false;
  bool waiting_reported_ = false;
};

}  // namespace hapticd::teleop
