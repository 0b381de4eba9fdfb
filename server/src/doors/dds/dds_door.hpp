#pragma once
// The DDS door (docs/dds-interface.md): the gate's adapter to DDS. It owns the participant and the topics and
// translates both ways:
//   in   CommandIntake, a listener on Cyclone's receive threads: each engine command (and each part of a group
//        command) to Gate::admit, its writer's participant as the peer (PeerDirectory) and the writer as its
//        channel; a request waiting wakes the gate's service thread, which calls answer_requests (here: take
//        them, RequestDispatcher::answer, write the replies);
//   out  the gate's sinks (Door): states, group states, descriptions, events, fault reports, telemetry as
//        samples on their topics;
//   presence  a claim's channel is its request writer (still matched?); a peer is alive while one of its command
//        writers' liveliness holds.
// It also takes the haptic scene's requests on a thread of their own (SceneIntake), relays the engines' worlds to
// the live view (WorldRelay) and counts the DDS deadlines engines miss.
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "config/session_config.hpp"
#include "doors/dds/command_intake.hpp"
#include "doors/dds/dds_endpoints.hpp"
#include "doors/dds/scene_intake.hpp"
#include "doors/dds/world_relay.hpp"
#include "gate/door.hpp"
#include "gate/gate.hpp"

namespace hapticd::server {

class DdsDoor final : public Door {
 public:
  // Creates the participant and the topics. cpus: the CPUs the DDS threads run on (empty: no pinning): Cyclone's
  // threads start with the participant and inherit them. Cross-CPU wake-ups dominate the round trip on small
  // machines; keeping the DDS path off the loop's CPU and on one set of CPUs makes it several times shorter
  // (docs/dds-interface.md). Throws std::runtime_error when DDS cannot be set up.
  DdsDoor(const DdsSettings& settings, Gate& gate, const std::vector<int>& cpus);
  ~DdsDoor() override;
  DdsDoor(const DdsDoor&) = delete;
  DdsDoor& operator=(const DdsDoor&) = delete;

  [[nodiscard]] const dds::Participant& participant() const noexcept { return dds_->participant; }
  // Before start(): the engines' worlds (hapticd_world), checked, go to `sink` (the live view's) from now on.
  void relay_worlds(std::function<void(const hapticd_msg_World&)> sink);
  [[nodiscard]] std::uint64_t worlds_relayed() const noexcept { return worlds_ ? worlds_->accepted() : 0; }
  [[nodiscard]] std::uint64_t worlds_rejected() const noexcept { return worlds_ ? worlds_->rejected() : 0; }
  [[nodiscard]] std::uint64_t deadline_misses(std::size_t device) const { return intake_->deadline_misses(device); }
  // The haptic scene's intake (null: the session has no scene).
  [[nodiscard]] const SceneIntake* scene() const noexcept { return scene_.get(); }

  // Door.
  [[nodiscard]] DoorKind kind() const noexcept override { return DoorKind::dds; }
  [[nodiscard]] bool channel_open(const Sender& s) const override;
  [[nodiscard]] bool alive(const PeerId& p) override;
  void answer_requests(RequestDispatcher& dispatcher) override;
  void service() override;
  void state(std::size_t device, const DeviceSnapshot& s, const hapticd_msg_DeviceState& m) override;
  void repeat_state(const hapticd_msg_DeviceState& m) override;
  void group_state(const hapticd_msg_GroupState& m, bool repeat) override;
  void description(const hapticd_msg_DeviceDescription& m) override;
  void group_description(const hapticd_msg_GroupDescription& m) override;
  void fault_report(const hapticd_msg_FaultReport& m) override;
  void telemetry(const hapticd_msg_Telemetry& m) override;
  void event(const hapticd_msg_Event& m) override;
  void start() override;
  void stop() override;

 private:
  // The readers' topic filters (Cyclone's receive threads): samples for another device are dropped before the
  // reader stores them - an attacker inventing device names creates no state - and counted.
  static bool command_for_us(const void* sample, void* self);
  static bool request_for_us(const void* sample, void* self);
  static bool group_command_for_us(const void* sample, void* self);

  Gate& gate_;
  dds_topic_filter command_filter_, request_filter_, group_command_filter_;
  std::unique_ptr<DdsEndpoints> dds_;
  std::unique_ptr<CommandIntake> intake_;
  std::unique_ptr<SceneIntake> scene_;  // after dds_: it uses the participant and the peers; null: no scene
  std::unique_ptr<WorldRelay> worlds_;
  std::chrono::steady_clock::time_point next_log_report_;
};

}  // namespace hapticd::server
