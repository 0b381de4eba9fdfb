#pragma once
// The server's side of a teleoperation link (the `teleoperation` section; docs/teleoperation.md): its device is
// the master or the remote of a bilateral link to another server's device, over the DDS topic hapticd_teleop.
// It is a door of the gate (gate/door.hpp) whose one peer is the link itself (PeerId::link): it holds the device's
// claim for the whole session, as an engine would (owner "teleoperation:<peer>"), so no engine can command the
// device meanwhile. The gate's publisher thread runs it with each published state of the device (Door::state):
// take the peer's packets (each checked - a malformed one is dropped, counted and reported, never applied - and
// only the newest kept), run the link's side (teleop::TeleopSide: the control law and the passivity controller),
// hand the force to the loop as the engine's input (lock-free; it fades at the engine deadline if the link stops
// running), and send this side's packet.
// Who may speak for the peer (docs/teleoperation.md, "Binding"): each side writes its packets in a DDS partition of
// its own device ("hapticd.teleop.<device>"), and reads only its peer's - with DDS Security, the permissions grant
// that partition to the peer server's identity alone. The link binds to the writer of the first valid packet; a
// packet from any other writer is rejected and counted while the bound writer is matched (an impostor, even one
// with the right names and role); once the bound writer is gone (its server ended or its lease ran out), the next
// valid writer re-binds the link: its serials and energy start afresh and the side re-anchors (a restarted peer
// takes the link up again). A peer's energy is credited only as far as the link's own force and motion could have
// carried it (teleop::TeleopSide), so the report's figures stay true whatever a packet claims. Safety: a peer that
// reports itself stopped stops this device too (an emergency stop), so either side's stop stops both; the remote stops
// when the link has been silent for link_timeout_s; the master's force fades out then and back in when the link
// returns. After a recovery the side starts again from where its handle is (no jump towards the peer).
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "config/teleoperation_settings.hpp"
#include "gate/device_gate.hpp"
#include "gate/door.hpp"
#include "gate/event_fanout.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "hapticd/teleop/teleop_port.hpp"
#include "hapticd_msg.h"
#include "session/device_snapshot.hpp"
#include "session/teleop_phase.hpp"

namespace hapticd::server {

class TeleopLink final : public Door {
 public:
  // Claims `device` for the link (it is free: the gate is being built). Throws std::runtime_error when the DDS
  // entities cannot be created.
  // `real_time`: the loop runs on a real clock (the packets are timed by the monotonic clock when they are sent and
  // taken), else on a virtual one (a state's time is the present).
  TeleopLink(const TeleoperationSettings& settings, DeviceGate& device, TeleopPhase& phase,
             const dds::Participant& participant, EventFanout& events, bool real_time);

  [[nodiscard]] std::size_t device() const noexcept { return device_.index; }
  // Door: the link's peer is itself (the session holds its claim); a new state of the linked device carries its
  // packets (on_state).
  [[nodiscard]] DoorKind kind() const noexcept override { return DoorKind::link; }
  [[nodiscard]] bool channel_open(const Sender&) const override { return true; }
  [[nodiscard]] bool alive(const PeerId&) override { return true; }
  void state(std::size_t device, const DeviceSnapshot& snapshot, const hapticd_msg_DeviceState&) override {
    if (device == device_.index) on_state(snapshot);
  }
  // Publisher thread: a new state of the linked device.
  void on_state(const DeviceSnapshot& snapshot);

  // Any thread.
  [[nodiscard]] std::uint64_t packets_sent() const noexcept { return sent_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t packets_taken() const noexcept { return taken_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t packets_rejected() const noexcept { return rejected_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t stops() const noexcept { return stops_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t losses() const noexcept { return losses_.load(std::memory_order_relaxed); }
  // Valid packets from a writer other than the bound peer's while it was there; times the link was (re-)bound.
  [[nodiscard]] std::uint64_t impostor_packets() const noexcept { return impostors_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t bindings() const noexcept { return bindings_.load(std::memory_order_relaxed); }
  // This port's energies [J]: in, out, dissipated by its passivity controller; the lowest observed energy (what
  // entered at the peer's port, as received, minus what left here: below zero only without passivity control);
  // the largest force the link applied here [N]; the peer's energy in as its packets claimed it and as credited
  // (this side's units) [J].
  struct Energy {
    double in = 0.0, out = 0.0, dissipated = 0.0, lowest_observed = 0.0, max_force_n = 0.0;
    double peer_claimed = 0.0, peer_credited = 0.0;
    double max_torque_n_m = 0.0;  // the largest torque the link applied here (rotation) [N m]
  };
  [[nodiscard]] Energy energy() const noexcept;
  // The link's delay as this side measures it from the packets' times (teleop/link_clock.hpp) [s]: the shortest
  // round trip of the last 2 s, the peer's clock offset (its clock minus this one's), the mean one-way delays
  // to and from this side; exchanges taken and refused (impossible times).
  struct Delay {
    bool valid = false;
    double round_trip_s = 0.0, offset_s = 0.0, mean_in_s = 0.0, mean_out_s = 0.0;
    std::uint64_t samples = 0, refused = 0;
  };
  [[nodiscard]] Delay delay() const noexcept;
  [[nodiscard]] const TeleoperationSettings& settings() const noexcept { return settings_; }

 private:
  // Each packet arrives when it is taken: the link's clock read after the take (real time), or the state's time.
  void take_packets(std::int64_t state_ns);
  // The link's clock now: real time, the monotonic clock from the link's origin; else the state's time.
  [[nodiscard]] std::int64_t link_now(std::int64_t state_ns) const noexcept;
  // Whether `writer` may speak for the peer: binds the link to it when it is unbound or its bound writer is gone;
  // else (an impostor) counts and reports it and returns false.
  bool admit(dds_instance_handle_t writer);
  [[nodiscard]] bool matched(dds_instance_handle_t writer) const;
  void reject(std::string_view code, std::string_view problem, std::atomic<std::uint64_t>& counter);
  // The loop's port stopped the device (its E-stop, requested in the loop): counted, logged, an event.
  void stopped(teleop::PortStop stop, const std::string& message);
  // What the loop's newest report tells: the events it decided and the figures.
  void report();

  TeleoperationSettings settings_;
  DeviceGate& device_;
  EventFanout& events_;
  std::string name_;  // the linked device's
  dds::Reader<hapticd_msg_TeleopPacket> reader_;
  dds::Writer<hapticd_msg_TeleopPacket> writer_;
  TeleopPhase& phase_;  // the link's side in the device's cycle: this door carries its packets and reports
  hapticd_msg_TeleopPacket packet_{};
  bool real_time_;
  std::int64_t origin_ns_ = 0;       // real time: the monotonic clock's reading at the link clock's zero
  bool started_ = false;             // a state seen (origin_ns_ set)
  TeleopReport seen_;                // the report the events were said for
  dds_instance_handle_t bound_ = 0;  // the peer's writer (0: none yet)
  std::atomic<std::uint64_t> sent_{0}, taken_{0}, rejected_{0}, stops_{0}, losses_{0}, impostors_{0}, bindings_{0};
  std::atomic<double> in_{0.0}, out_{0.0}, dissipated_{0.0}, lowest_observed_{0.0}, max_force_{0.0};
  std::atomic<double> peer_claimed_{0.0}, peer_credited_{0.0}, max_torque_{0.0};
  std::atomic<bool> delay_valid_{false};
  std::atomic<double> round_trip_{0.0}, offset_{0.0}, mean_in_{0.0}, mean_out_{0.0};
  std::atomic<std::uint64_t> delay_samples_{0}, delay_refused_{0};
};

}  // namespace hapticd::server
