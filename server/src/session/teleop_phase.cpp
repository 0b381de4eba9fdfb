#include "session/teleop_phase.hpp"

#include <algorithm>

namespace hapticd::server {

TeleopPhase::TeleopPhase(teleop::Role role, const teleop::LinkSettings& settings) : port_(role, settings) {
  input_.has_wrench = true;
}

bool TeleopPhase::deliver(const teleop::LinkPacket& packet, std::int64_t arrival_ns) noexcept {
  if (marker_pending_) push_marker();  // the new peer's packets only after its marker: else dropped, counted
  Arrival a;
  a.packet = packet;
  a.arrival_ns = arrival_ns;
  if (!marker_pending_ && inbox_.try_push(a)) return true;
  dropped_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

void TeleopPhase::peer_changed() noexcept {
  // In the ring, in order with the packets: those before it are the old peer's. With no room it waits for room, and
  // the new peer's packets wait behind it.
  marker_pending_ = true;
  push_marker();
}

void TeleopPhase::push_marker() noexcept {
  Arrival a;
  a.peer_changed = true;
  marker_pending_ = !inbox_.try_push(a);
}

void TeleopPhase::cycle(std::int64_t time_ns, const ChainState& state, bool stopped, bool ending) noexcept {
  Arrival a;
  while (inbox_.try_pop(a)) {
    if (a.peer_changed) {
      port_.peer_changed();
    } else {
      port_.receive(a.packet, a.arrival_ns);
    }
  }
  teleop::LocalSample sample;
  sample.time_ns = time_ns;
  sample.position = state.handle_pose.position;
  sample.velocity = state.handle_twist.linear;
  sample.force = state.operator_wrench.force;  // what holds the handle: the remote's environment
  sample.orientation = state.handle_pose.orientation;
  sample.angular_velocity = state.handle_twist.angular;
  sample.torque = state.operator_wrench.torque;
  if (!started_) {
    started_ = true;
    last_ns_ = time_ns;
  }
  const double dt = std::clamp(static_cast<double>(time_ns - last_ns_) * 1e-9, 1e-5, 0.1);
  last_ns_ = time_ns;
  const teleop::PortCycle out = port_.cycle(sample, dt, stopped, ending);

  apply_ = out.apply;
  stop_ = out.stop;
  input_.wrench.force = out.force;
  input_.wrench.torque = out.torque;
  ++input_.sequence;
  outbox_.publish(out.packet);

  // The report: translation's port and rotation's summed; each port's observed energy is its own (neither pays for
  // the other), so the lowest is either's.
  const teleop::SideStatus& st = port_.status();
  const teleop::EnergyPort& port = *st.port;
  const teleop::EnergyPort& turn = *st.rotation_port;
  TeleopReport& r = report_;
  r.energy_in = port.energy_in() + turn.energy_in();
  r.energy_out = port.energy_out() + turn.energy_out();
  r.dissipated = port.dissipated() + turn.dissipated();
  r.peer_claimed = st.peer_energy_in + st.peer_rotation_energy_in;
  r.peer_credited = st.peer_energy_credited + st.peer_rotation_energy_credited;
  if (st.received > 0) r.lowest_observed = std::min({r.lowest_observed, port.observed(), turn.observed()});
  r.max_force = std::max(r.max_force, out.force.norm());
  r.max_torque = std::max(r.max_torque, out.torque.norm());
  r.clock = st.clock;
  r.received = st.received;
  if (out.lost) {
    ++r.losses;
    r.silence_s = st.silence_s;
  }
  if (out.back) ++r.backs;
  if (out.stop == teleop::PortStop::peer_stopped) ++r.peer_stops;
  if (out.stop == teleop::PortStop::link_lost) ++r.lost_stops;
  if (out.waiting) r.waiting = true;
  r.dropped = dropped_.load(std::memory_order_relaxed);
  reports_.publish(r);
}

}  // namespace hapticd::server
