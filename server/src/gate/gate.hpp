#pragma once
// The gate (docs/architecture.md, "The gate and its doors"): everything that decides what reaches the devices
// from outside, whichever door it came through - claims, command admission (owner, order, freshness, bounds),
// requests, E-stop latches and peers - and what goes out to every door (states, events, descriptions, fault
// reports, telemetry). It knows no transport: DDS, the engine socket and the teleoperation link are doors
// (gate/door.hpp) that translate their wire to these calls. Threads, none of them the loop's:
//   publisher thread  StateFanout: woken by the loop after each cycle (futex, no lock), takes the devices'
//                     snapshots (lock-free LatestValue), hands each state to every door, and the events it reveals;
//   service thread    woken by a door (a request waiting, a peer gone) and at least every 50 ms: each door answers
//                     its waiting requests through the RequestDispatcher, the claims of departed peers end, each
//                     door does its periodic duties, telemetry goes out;
//   a door's thread   admit(): a command through the CommandGate, an accepted one handed to the loop
//                     (DeviceRequests::engine_input, lock-free);
//   loop thread       after_cycle(): wakes the publisher; LockstepSync, in lockstep, waits (wall time, bounded)
//                     until the owning engine has answered the state just published.
#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string_view>
#include <thread>
#include <vector>

#include "config/session_config.hpp"
#include "executor/executor.hpp"
#include "gate/device_gate.hpp"
#include "gate/door.hpp"
#include "gate/event_fanout.hpp"
#include "gate/lockstep_sync.hpp"
#include "gate/request_dispatcher.hpp"
#include "gate/scene_gate.hpp"
#include "gate/state_fanout.hpp"
#include "safety/fault_history.hpp"

namespace hapticd::server {

class DeviceSession;

class Gate final : public CycleListener {
 public:
  // cpus: the CPUs the gate's threads run on (the doors' CPUs, off the loop's; empty: no pinning).
  Gate(const GateSettings& settings, double rate_hz, std::vector<DeviceSession*> sessions,
       std::vector<GroupStage*> stages = {}, std::vector<int> cpus = {});
  ~Gate() override;
  Gate(const Gate&) = delete;
  Gate& operator=(const Gate&) = delete;

  // Before start(): a door (at most one of each kind). States reach the doors in the order they were added.
  void add_door(Door& door);
  // Before start(): where the live statistics of the loop that drives `device` are (the executor's).
  void set_loop_statistics(std::size_t device, const LiveLoopStatistics* live) noexcept {
    states_.set_loop_statistics(device, live);
  }
  // Publishes the descriptions, starts the threads, then the doors.
  void start();
  // Stops the doors (no more input), joins the threads; publishes the final states and telemetry. Idempotent.
  void stop();

  void after_cycle(std::uint64_t index, bool lockstep) noexcept override;
  // Any thread: the service thread runs now (a door has requests waiting, a peer changed).
  void wake() noexcept;

  // A door's thread: a command from `sender` through the gate; accepted, it goes to the loop. source_ns: when
  // the sender wrote it by its own clock (a door that has no such stamp passes the time it received it), ns since
  // the epoch. A command naming no device of this server is malformed (counted).
  CommandGate::Verdict admit(const hapticd_msg_EngineCommand& c, const Sender& sender, std::int64_t source_ns);
  // ... for a device already found (a group command's parts).
  CommandGate::Verdict admit(DeviceGate& d, const hapticd_msg_EngineCommand& c, const Sender& sender,
                             std::int64_t source_ns);

  [[nodiscard]] DeviceGates& devices() noexcept { return devices_; }
  [[nodiscard]] const DeviceGates& devices() const noexcept { return devices_; }
  [[nodiscard]] RequestDispatcher& requests() noexcept { return *dispatcher_; }
  [[nodiscard]] EventFanout& events() noexcept { return events_; }
  // The session's haptic scene, for the doors' edits (null: the session has no `scene` section).
  [[nodiscard]] SceneGate* scene() noexcept { return scene_.get(); }
  [[nodiscard]] std::uint64_t snapshot_interval() const noexcept { return interval_; }

  // Any thread (the server's monitor, which takes the reports from the devices): a fault report to every door.
  void publish_fault_report(std::size_t device, const FaultReport& report);
  // Any thread: an event about the whole session (e.g. EVENT_RECORDING), sent for every device.
  void announce(hapticd_msg_EventKind kind, std::string_view code, std::string_view message);

  // Any thread, while running or after stop().
  [[nodiscard]] std::uint64_t commands_accepted(std::size_t device) const;
  [[nodiscard]] std::uint64_t commands_rejected(std::size_t device) const;
  [[nodiscard]] std::array<std::uint64_t, dds::kRejectReasons> rejected_by_reason(std::size_t device) const;
  [[nodiscard]] std::string owner(std::size_t device) const;
  // Time from publishing a state to accepting the command that answers it, and the cycles until the loop applied
  // it, over the session and every device (RoundTripProbe).
  [[nodiscard]] RoundTripStatistics round_trip() const;
  [[nodiscard]] std::uint64_t lockstep_timeouts() const noexcept { return lockstep_.timeouts(); }
  [[nodiscard]] std::uint64_t unknown_device_commands() const noexcept { return devices_.unknown_device_commands(); }
  [[nodiscard]] std::uint64_t unknown_device_requests() const noexcept { return devices_.unknown_device_requests(); }
  [[nodiscard]] std::uint64_t claims_ended() const noexcept { return dispatcher_->claims_ended(); }

  // The service thread checks the claims at least this often (and whenever a door wakes it).
  static constexpr std::int64_t kServicePeriodNs = 50'000'000;

 private:
  void publisher_thread();
  void service_thread();
  void pin_this_thread() const;
  void wake_publisher() noexcept;

  GateSettings settings_;
  std::vector<int> cpus_;
  std::uint64_t interval_;
  DeviceGates devices_;
  EventFanout events_;
  StateFanout states_;
  std::unique_ptr<RequestDispatcher> dispatcher_;
  std::unique_ptr<SceneGate> scene_;
  LockstepSync lockstep_;
  std::vector<Door*> doors_;
  std::mutex admit_mutex_;  // one command at a time (every door's): the hand-over to a device has one producer

  std::atomic<std::uint32_t> ticket_{0};  // the loop -> the publisher (futex)
  std::atomic<bool> stopping_{false};
  std::mutex wake_mutex_;  // the doors -> the service thread
  std::condition_variable wake_cv_;
  bool woken_ = false;
  std::thread publisher_thread_, service_thread_;
  bool started_ = false;
};

}  // namespace hapticd::server
