#pragma once
// The server's DDS interface (docs/dds-interface.md): publishes every device's description, state, events and
// telemetry; takes engine commands and control requests. It runs on two threads of its own, never the loop:
//   publisher: woken by the loop after each cycle (futex, no lock), takes the devices' snapshots (lock-free
//              LatestValue) and writes the states, and the events the snapshots reveal (faults, scheme changes);
//   receiver:  waits on the command and request readers; validates every command (CommandGate) and hands an
//              accepted one to the loop (DeviceSession::publish_engine_input, lock-free); answers requests;
//              writes telemetry; watches the owning engine's liveliness and deadline.
// In lockstep with lockstep_sync, after_cycle() makes the loop wait (wall time, bounded) until the owning
// engine has answered the state just published, so end-to-end runs over DDS are repeatable.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "config/session_config.hpp"
#include "dds/command_gate.hpp"
#include "dds/round_trip_probe.hpp"
#include "safety/fault_history.hpp"
#include "executor/executor.hpp"
#include "hapticd_msg.h"

namespace hapticd::server {

class DeviceSession;

class DdsBridge final : public CycleListener {
 public:
  // Creates the participant, the topics and the per-device snapshot interval; publishes the descriptions.
  // dds_cpus: the CPUs the bridge's and Cyclone's threads run on (empty: no pinning). Cross-CPU wake-ups
  // dominate the round trip on small machines; keeping the DDS path off the loop's CPU and on one set of CPUs
  // makes it several times shorter (docs/dds-interface.md).
  DdsBridge(const DdsSettings& settings, double rate_hz, std::vector<DeviceSession*> sessions,
            std::vector<int> dds_cpus = {});
  ~DdsBridge() override;
  DdsBridge(const DdsBridge&) = delete;
  DdsBridge& operator=(const DdsBridge&) = delete;

  // Before start(): where the loop's live statistics are (the executor's).
  void set_loop_statistics(const LiveLoopStatistics* live) noexcept { live_ = live; }
  void start();  // the two threads
  void stop();   // joins them; publishes the final states and telemetry first

  void after_cycle(std::uint64_t index, bool lockstep) noexcept override;
  // Any thread (the server's monitor, which takes the reports from the devices): publishes a fault report.
  void publish_fault_report(std::size_t device, const FaultReport& report);
  // Any thread: an event about the whole session (e.g. EVENT_RECORDING), sent for every device.
  void announce(int kind, std::string_view code, std::string_view message);

  // Any thread, while running or after stop().
  [[nodiscard]] std::uint64_t commands_accepted(std::size_t device) const;
  [[nodiscard]] std::uint64_t commands_rejected(std::size_t device) const;
  [[nodiscard]] std::array<std::uint64_t, dds::kRejectReasons> rejected_by_reason(std::size_t device) const;
  [[nodiscard]] std::string owner(std::size_t device) const;
  [[nodiscard]] std::uint64_t deadline_misses(std::size_t device) const;
  // Time from writing a state to accepting the command that answers it, and the cycles until the loop applied
  // it, over the session and every device (RoundTripProbe).
  [[nodiscard]] RoundTripStatistics round_trip() const;
  [[nodiscard]] std::uint64_t lockstep_timeouts() const noexcept { return lockstep_timeouts_.load(); }
  // Engine commands naming a device this server does not have (malformed; rejected, never applied).
  [[nodiscard]] std::uint64_t unknown_device_commands() const noexcept { return unknown_device_commands_.load(); }
  // Requests naming a device this server does not have (dropped unanswered: another server may have it).
  [[nodiscard]] std::uint64_t unknown_device_requests() const noexcept { return unknown_device_requests_.load(); }
  // Claims that ended because their claimant's participant was gone (not released).
  [[nodiscard]] std::uint64_t claims_ended() const noexcept { return claims_ended_.load(); }

 private:
  struct Device;
  struct Dds;

  void publisher_thread();
  void receiver_thread();
  void publish_states();
  void handle_commands();
  void handle_requests();
  void check_claims();
  void check_engine_deadlines();
  void publish_telemetry();
  void publish_description(Device& d);
  void fill_loop_summary(hapticd_msg_LoopSummary& loop) const;
  void send_event(Device& d, int kind, std::string_view code, std::string_view message);

  void pin_this_thread() const;
  [[nodiscard]] bool serves(std::string_view device) const noexcept;
  // The readers' topic filters (Cyclone's receive threads): only samples for this server's devices are stored.
  static bool command_for_us(const void* sample, void* self);
  static bool request_for_us(const void* sample, void* self);

  DdsSettings settings_;
  double rate_hz_;
  std::vector<int> cpus_;
  const LiveLoopStatistics* live_ = nullptr;
  std::uint64_t snapshot_interval_;
  std::vector<std::unique_ptr<Device>> devices_;
  std::unique_ptr<Dds> dds_;

  std::atomic<std::uint32_t> ticket_{0};
  std::atomic<bool> stopping_{false};
  std::thread publisher_, receiver_;
  std::atomic<std::uint64_t> event_serial_{0};
  std::atomic<std::uint64_t> lockstep_timeouts_{0};
  std::atomic<std::uint64_t> unknown_device_commands_{0};
  std::atomic<std::uint64_t> unknown_device_requests_{0};
  std::atomic<std::uint64_t> claims_ended_{0};
  // The receiver checks the claims at least this often (and whenever a command writer's liveliness changes).
  static constexpr std::int64_t kClaimCheckPeriodNs = 50'000'000;
  std::mutex command_take_mutex_;
};

}  // namespace hapticd::server
