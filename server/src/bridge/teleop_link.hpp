#pragma once
// The server's side of a teleoperation link (the `teleoperation` section; docs/teleoperation.md): its device is
// the master or the remote of a bilateral link to another server's device, over the DDS topic hapticd_teleop.
// It holds the device's claim for the whole session, as an engine would (owner "teleoperation:<peer>"): no engine
// can command the device meanwhile. The publisher thread runs it with each published state of the device:
// take the peer's packets (each checked - a malformed one is dropped, counted and reported, never applied - and
// only the newest kept), run the link's side (teleop::TeleopSide: the control law and the passivity controller),
// hand the force to the loop as the engine's input (lock-free; it fades at the engine deadline if the link stops
// running), and send this side's packet. Safety: a peer that reports itself stopped stops this device too (an
// emergency stop), so either side's stop stops both; the remote stops when the link has been silent for
// link_timeout_s; the master's force fades out then and back in when the link returns. After a recovery the
// side starts again from where its handle is (no jump towards the peer).
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "bridge/device_link.hpp"
#include "bridge/event_sender.hpp"
#include "config/teleoperation_settings.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "hapticd/teleop/teleop_side.hpp"
#include "hapticd_msg.h"
#include "session/device_snapshot.hpp"

namespace hapticd::server {

class TeleopLink {
 public:
  // Claims `device` for the link (it is free: the bridge is being built). Throws std::runtime_error when the DDS
  // entities cannot be created.
  TeleopLink(const TeleoperationSettings& settings, DeviceLink& device, const dds::Participant& participant,
             EventSender& events);

  [[nodiscard]] std::size_t device() const noexcept { return device_.index; }
  // Publisher thread: a new state of the linked device.
  void on_state(const DeviceSnapshot& snapshot);

  // Any thread.
  [[nodiscard]] std::uint64_t packets_sent() const noexcept { return sent_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t packets_taken() const noexcept { return taken_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t packets_rejected() const noexcept { return rejected_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t stops() const noexcept { return stops_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t losses() const noexcept { return losses_.load(std::memory_order_relaxed); }
  // This port's energies [J]: in, out, dissipated by its passivity controller; the lowest observed energy (what
  // entered at the peer's port, as received, minus what left here: below zero only without passivity control);
  // the largest force the link applied here [N].
  struct Energy {
    double in = 0.0, out = 0.0, dissipated = 0.0, lowest_observed = 0.0, max_force_n = 0.0;
  };
  [[nodiscard]] Energy energy() const noexcept;
  [[nodiscard]] const TeleoperationSettings& settings() const noexcept { return settings_; }

 private:
  void take_packets();
  void stop_device(std::string_view code, const std::string& message);

  TeleoperationSettings settings_;
  DeviceLink& device_;
  EventSender& events_;
  std::string name_;  // the linked device's
  dds::Reader<hapticd_msg_TeleopPacket> reader_;
  dds::Writer<hapticd_msg_TeleopPacket> writer_;
  teleop::TeleopSide side_;
  hapticd_msg_TeleopPacket packet_{};
  std::int64_t last_ns_ = 0;
  std::uint64_t engine_sequence_ = 0;
  bool started_ = false;
  bool was_stopped_ = false;
  bool lost_reported_ = false;
  bool peer_stop_seen_ = false;
  std::atomic<std::uint64_t> sent_{0}, taken_{0}, rejected_{0}, stops_{0}, losses_{0};
  std::atomic<double> in_{0.0}, out_{0.0}, dissipated_{0.0}, lowest_observed_{0.0}, max_force_{0.0};
};

}  // namespace hapticd::server
