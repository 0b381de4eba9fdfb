#include "hapticd/teleop/teleop_port.hpp"

namespace hapticd::teleop {

const char* stop_code(PortStop stop) noexcept {
  switch (stop) {
    case PortStop::peer_stopped:
      return "teleoperation_peer_stopped";
    case PortStop::link_lost:
      return "teleoperation_link_lost";
    case PortStop::none:
      break;
  }
  return "";
}

PortCycle TeleopPort::cycle(const LocalSample& sample, double dt, bool stopped, bool ending) noexcept {
  PortCycle c;
  if (!started_) {
    side_.start(sample);
    started_ = true;
  }
  if (was_stopped_ && !stopped) side_.rebase(sample);  // recovered: on from here, no pull towards the peer
  was_stopped_ = stopped;
  const SideOutput out = side_.cycle(sample, dt, stopped);
  const SideStatus& st = side_.status();
  c.packet = out.packet;
  c.force = out.force;
  c.torque = out.torque;
  c.apply = !stopped && !ending;

  // The peer's stop stops this side - on the stop itself, not while it lasts: this side may recover before the
  // peer does (its force stays faded out until the peer runs again).
  if (st.peer_stopped && !peer_stop_seen_) {
    peer_stop_seen_ = true;
    if (!stopped) c.stop = PortStop::peer_stopped;
  } else if (!st.peer_stopped) {
    peer_stop_seen_ = false;
  }
  if (st.waiting && !waiting_reported_) {
    waiting_reported_ = true;
    c.waiting = true;
  }
  // A silent link stops the remote (its setpoint already holds still); the master's force fades (TeleopSide).
  if (st.link_lost && !lost_reported_) {
    lost_reported_ = true;
    c.lost = true;
    if (side_.role() == Role::remote && !stopped && c.stop == PortStop::none) c.stop = PortStop::link_lost;
  } else if (!st.link_lost && lost_reported_) {
    lost_reported_ = false;
    c.back = true;
  }
  if (c.stop != PortStop::none) c.apply = false;
  return c;
}

}  // namespace hapticd::teleop
