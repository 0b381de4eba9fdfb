#pragma once
// The server's DDS interface (docs/dds-interface.md), composed by thread - never the loop's:
//   publisher thread  StatePublisher: woken by the loop after each cycle (futex, no lock), takes the devices'
//                     snapshots (lock-free LatestValue), writes the states and the events they reveal;
//   Cyclone's receive CommandIntake: a listener that validates every engine command (CommandGate, PeerDirectory)
//   threads           and hands an accepted one to the loop (DeviceRequests::engine_input, lock-free);
//   receiver thread   RequestDispatcher: answers requests, ends claims whose claimant is gone, counts missed
//                     deadlines; and writes telemetry;
//   socket thread     EngineSocket (when the session has an engine_socket section): the same gate for clients
//                     without DDS, over WebSocket/JSON - their commands to CommandIntake, their requests to the
//                     receiver's RequestDispatcher, the states from the StatePublisher;
//   (publisher thread) TeleopLink (when the session has a teleoperation section): with each state of its device,
//                     the peer server's packets in, the link's force to the loop, this side's packet out;
//   loop thread       LockstepSync: in lockstep, after_cycle() waits (wall time, bounded) until the owning engine
//                     has answered the state just published, so end-to-end runs over DDS are repeatable.
// The parts share the per-device links (DeviceLinks) and the DDS entities (DdsEndpoints).
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "bridge/command_intake.hpp"
#include "bridge/dds_endpoints.hpp"
#include "bridge/device_link.hpp"
#include "bridge/engine_socket.hpp"
#include "bridge/event_sender.hpp"
#include "bridge/lockstep_sync.hpp"
#include "bridge/request_dispatcher.hpp"
#include "bridge/state_publisher.hpp"
#include "bridge/teleop_link.hpp"
#include "bridge/world_relay.hpp"
#include "config/session_config.hpp"
#include "executor/executor.hpp"
#include "safety/fault_history.hpp"

namespace hapticd::server {

class DeviceSession;

class DdsBridge final : public CycleListener {
 public:
  // Creates the participant, the topics and the per-device snapshot interval; publishes the descriptions.
  // dds_cpus: the CPUs the bridge's and Cyclone's threads run on (empty: no pinning). Cross-CPU wake-ups
  // dominate the round trip on small machines; keeping the DDS path off the loop's CPU and on one set of CPUs
  // makes it several times shorter (docs/dds-interface.md).
  // stages: the session's device groups (their descriptions, group states and group requests).
  // socket: the engine socket's settings (not enabled: none); its port is bound here (an error names it).
  // teleop: the teleoperation link's settings (not enabled: none); the link claims its device here.
  DdsBridge(const DdsSettings& settings, double rate_hz, std::vector<DeviceSession*> sessions,
            std::vector<GroupStage*> stages = {}, std::vector<int> dds_cpus = {},
            const EngineSocketSettings& socket = {}, const TeleoperationSettings& teleop = {});
  ~DdsBridge() override;
  DdsBridge(const DdsBridge&) = delete;
  DdsBridge& operator=(const DdsBridge&) = delete;

  // Before start(): where the live statistics of the loop that drives `device` are (the executor's).
  void set_loop_statistics(std::size_t device, const LiveLoopStatistics* live) noexcept {
    publisher_->set_loop_statistics(device, live);
  }
  void start();  // the publisher and receiver threads
  void stop();   // joins them; publishes the final states and telemetry first

  void after_cycle(std::uint64_t index, bool lockstep) noexcept override;
  // Any thread (the server's monitor, which takes the reports from the devices): publishes a fault report.
  void publish_fault_report(std::size_t device, const FaultReport& report);
  // Any thread: an event about the whole session (e.g. EVENT_RECORDING), sent for every device.
  void announce(hapticd_msg_EventKind kind, std::string_view code, std::string_view message);

  // Any thread, while running or after stop().
  [[nodiscard]] std::uint64_t commands_accepted(std::size_t device) const;
  [[nodiscard]] std::uint64_t commands_rejected(std::size_t device) const;
  [[nodiscard]] std::array<std::uint64_t, dds::kRejectReasons> rejected_by_reason(std::size_t device) const;
  [[nodiscard]] std::string owner(std::size_t device) const;
  [[nodiscard]] std::uint64_t deadline_misses(std::size_t device) const;
  // Time from writing a state to accepting the command that answers it, and the cycles until the loop applied
  // it, over the session and every device (RoundTripProbe).
  [[nodiscard]] RoundTripStatistics round_trip() const;
  [[nodiscard]] std::uint64_t lockstep_timeouts() const noexcept { return lockstep_->timeouts(); }
  // Engine commands naming a device this server does not have (malformed; rejected, never applied).
  [[nodiscard]] std::uint64_t unknown_device_commands() const noexcept { return links_.unknown_device_commands(); }
  // Requests naming a device this server does not have (dropped unanswered: another server may have it).
  [[nodiscard]] std::uint64_t unknown_device_requests() const noexcept { return links_.unknown_device_requests(); }
  // Claims that ended because their claimant's participant was gone (not released).
  [[nodiscard]] std::uint64_t claims_ended() const noexcept { return dispatcher_->claims_ended(); }
  // Before start(): the engines' worlds (hapticd_world), checked, go to `sink` (the live view's) from now on.
  void relay_worlds(std::function<void(const hapticd_msg_World&)> sink);
  // Worlds relayed and dropped as malformed (0 without relay_worlds).
  [[nodiscard]] std::uint64_t worlds_relayed() const noexcept { return worlds_ ? worlds_->accepted() : 0; }
  [[nodiscard]] std::uint64_t worlds_rejected() const noexcept { return worlds_ ? worlds_->rejected() : 0; }
  // The engine socket (nullptr: the session has none).
  [[nodiscard]] const EngineSocket* engine_socket() const noexcept { return socket_.get(); }
  // The teleoperation link (nullptr: the session has none).
  [[nodiscard]] const TeleopLink* teleop_link() const noexcept { return link_.get(); }

 private:
  void publisher_thread();
  void receiver_thread();
  void pin_this_thread() const;
  void wake_publisher() noexcept;

  DdsSettings settings_;
  std::vector<int> cpus_;
  DeviceLinks links_;
  std::unique_ptr<DdsEndpoints> dds_;
  std::unique_ptr<EventSender> events_;
  std::unique_ptr<StatePublisher> publisher_;
  std::unique_ptr<CommandIntake> intake_;
  std::unique_ptr<RequestDispatcher> dispatcher_;
  std::unique_ptr<LockstepSync> lockstep_;
  std::unique_ptr<EngineSocket> socket_;
  std::unique_ptr<WorldRelay> worlds_;
  std::unique_ptr<TeleopLink> link_;

  std::atomic<std::uint32_t> ticket_{0};  // the loop -> the publisher (futex)
  std::atomic<bool> stopping_{false};
  std::thread publisher_thread_, receiver_thread_;
  // The receiver checks the claims at least this often (and whenever a command writer's liveliness changes).
  static constexpr std::int64_t kClaimCheckPeriodNs = 50'000'000;
};

}  // namespace hapticd::server
