#pragma once
// The teleoperation link's side in the loop's cycle (docs/teleoperation.md, "One control path"): the device's
// TeleopPort - the control law, the passivity controller and the link's policies - runs in the device's cycle,
// between estimating the state and the chain, on the packets a transport handed over lock-free; its force reaches
// the chain in the same cycle. The transport (the server's TeleopLink over DDS) only carries packets: it delivers
// each one it takes with its arrival time, sends the newest packet the loop made, and reports what the loop tells it.
//
// Threads: the loop thread calls cycle() and reads the decision; one transport thread calls deliver(),
// peer_changed(), take_outgoing() and take_report(). The hand-offs are a ring (the packets, every one: each is an
// exchange of the link's clock) and two triple buffers (the newest packet out, the newest report). The cycle never
// allocates, locks or throws.
#include <Eigen/Core>
#include <atomic>
#include <cstdint>

#include "hapticd/chain_state.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/realtime/latest_value.hpp"
#include "hapticd/realtime/spsc_ring.hpp"
#include "hapticd/teleop/teleop_port.hpp"

namespace hapticd::server {

// What the loop tells the transport after each cycle: the link's energies, its clock and what happened (counters
// since the start: a reader that skips reports misses no event).
struct TeleopReport {
  double energy_in = 0.0, energy_out = 0.0, dissipated = 0.0;  // translation's and rotation's ports summed [J]
  double lowest_observed = 0.0;                    // either port's lowest observed energy since the first packet [J]
  double peer_claimed = 0.0, peer_credited = 0.0;  // the peer's energy in, as claimed and as credited [J]
  double max_force = 0.0, max_torque = 0.0;        // the largest the link commanded [N], [N m]
  teleop::LinkClockFigures clock;
  double silence_s = 0.0;               // at the newest loss
  std::uint64_t received = 0;           // packets the port took
  std::uint64_t losses = 0, backs = 0;  // the link lost, back
  std::uint64_t peer_stops = 0;         // the device stopped because the peer stopped
  std::uint64_t lost_stops = 0;         // the device stopped because the link was lost (the remote)
  bool waiting = false;                 // no packet yet after link_timeout_s (said once)
  std::uint64_t dropped = 0;            // packets the inbox had no room for
};

class TeleopPhase {
 public:
  // Throws std::invalid_argument with teleop::link_settings_problem().
  TeleopPhase(teleop::Role role, const teleop::LinkSettings& settings);

  // The transport's thread. A packet from the peer and its arrival on the link's clock; false when the inbox is
  // full (the loop has not run for 256 packets): the packet is dropped and counted.
  bool deliver(const teleop::LinkPacket& packet, std::int64_t arrival_ns) noexcept;
  // The packets come from another sender from now on (a restarted peer: its serials and energy start afresh).
  void peer_changed() noexcept;
  // The newest packet the loop made since the last take, to send; false when none.
  bool take_outgoing(teleop::LinkPacket& packet) noexcept { return outbox_.take(packet); }
  // The loop's newest report since the last take; false when none.
  bool take_report(TeleopReport& report) noexcept { return reports_.take(report); }

  // The loop thread: the port's cycle on the device's state at `time_ns` (dt: since the last). `stopped`, the
  // device is in its safe state; `ending`, its session is ending or it is stopping. Takes every packet delivered.
  void cycle(std::int64_t time_ns, const ChainState& state, bool stopped, bool ending) noexcept;
  // The loop thread, after cycle(): the link's force for the chain (nullptr: none this cycle), and whether the device
  // must stop now (its E-stop).
  [[nodiscard]] const EngineInput* input() const noexcept { return apply_ ? &input_ : nullptr; }
  [[nodiscard]] teleop::PortStop stop() const noexcept { return stop_; }

 private:
  struct Arrival {
    teleop::LinkPacket packet;
    std::int64_t arrival_ns = 0;
    bool peer_changed = false;  // a marker, not a packet
  };

  teleop::TeleopPort port_;
  realtime::SpscRing<Arrival> inbox_{256};
  realtime::LatestValue<teleop::LinkPacket> outbox_;
  realtime::LatestValue<TeleopReport> reports_;
  std::atomic<std::uint64_t> dropped_{0};
  // The transport's: a peer change the ring had no room for yet.
  bool marker_pending_ = false;
  void push_marker() noexcept;
  // The loop's.
  TeleopReport report_;
  EngineInput input_;
  bool apply_ = false;
  teleop::PortStop stop_ = teleop::PortStop::none;
  std::int64_t last_ns_ = 0;
  bool started_ = false;
};

}  // namespace hapticd::server
