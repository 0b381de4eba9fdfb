#pragma once
// The session's gate and its doors, built from the session file (docs/architecture.md, "The gate and its doors"):
// the gate (gate/gate.hpp) with the `gate` section's settings, and a door for each section that asks for one -
// DDS (`dds`), the engine socket (`engine_socket`; with or without DDS), the teleoperation link (`teleoperation`;
// its packets travel over DDS), ROS 2's topics (`ros2`). The doors are added to the gate in the order a state
// reaches them: the link first (its round trip is the loop's), the socket (its hand-off returns at once), DDS's
// write, ROS 2's last (for watching).
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "config/session_config.hpp"
#include "doors/dds/dds_door.hpp"
#include "doors/ros2/ros2_door.hpp"
#include "doors/socket/engine_socket.hpp"
#include "doors/teleop/teleop_link.hpp"
#include "gate/gate.hpp"

namespace hapticd::server {

class DeviceSession;
class GroupStage;

class Doors final : public CycleListener {
 public:
  // cpus: the CPUs of the gate's and the doors' threads (empty: no pinning). Throws std::runtime_error naming
  // the door that cannot be opened (DDS, a port, the link's device).
  Doors(const SessionConfig& config, std::vector<DeviceSession*> sessions, std::vector<GroupStage*> stages = {},
        std::vector<int> cpus = {});
  ~Doors() override;
  Doors(const Doors&) = delete;
  Doors& operator=(const Doors&) = delete;

  // Before start(): where the live statistics of the loop that drives `device` are (the executor's).
  void set_loop_statistics(std::size_t device, const LiveLoopStatistics* live) noexcept {
    gate_->set_loop_statistics(device, live);
  }
  // Before start(): the engines' worlds (hapticd_world over DDS), checked, go to `sink` (the live view's).
  void relay_worlds(std::function<void(const hapticd_msg_World&)> sink);
  void start() { gate_->start(); }
  void stop() { gate_->stop(); }
  void after_cycle(std::uint64_t index, bool lockstep) noexcept override { gate_->after_cycle(index, lockstep); }

  [[nodiscard]] Gate& gate() noexcept { return *gate_; }
  [[nodiscard]] const DdsDoor* dds() const noexcept { return dds_.get(); }                    // nullptr: no dds section
  [[nodiscard]] const EngineSocket* engine_socket() const noexcept { return socket_.get(); }  // nullptr: none
  [[nodiscard]] const TeleopLink* teleop_link() const noexcept { return link_.get(); }        // nullptr: none
  [[nodiscard]] const Ros2Door* ros2() const noexcept { return ros2_.get(); }                 // nullptr: none

  // Any thread.
  void publish_fault_report(std::size_t device, const FaultReport& report) {
    gate_->publish_fault_report(device, report);
  }
  void announce(hapticd_msg_EventKind kind, std::string_view code, std::string_view message) {
    gate_->announce(kind, code, message);
  }
  [[nodiscard]] std::uint64_t commands_accepted(std::size_t device) const { return gate_->commands_accepted(device); }
  [[nodiscard]] std::uint64_t commands_rejected(std::size_t device) const { return gate_->commands_rejected(device); }
  [[nodiscard]] std::array<std::uint64_t, dds::kRejectReasons> rejected_by_reason(std::size_t device) const {
    return gate_->rejected_by_reason(device);
  }
  [[nodiscard]] std::string owner(std::size_t device) const { return gate_->owner(device); }
  // The DDS deadlines the device's engine missed (0 without DDS).
  [[nodiscard]] std::uint64_t deadline_misses(std::size_t device) const {
    return dds_ ? dds_->deadline_misses(device) : 0;
  }
  [[nodiscard]] RoundTripStatistics round_trip() const { return gate_->round_trip(); }
  [[nodiscard]] std::uint64_t lockstep_timeouts() const noexcept { return gate_->lockstep_timeouts(); }
  [[nodiscard]] std::uint64_t unknown_device_commands() const noexcept { return gate_->unknown_device_commands(); }
  [[nodiscard]] std::uint64_t unknown_device_requests() const noexcept { return gate_->unknown_device_requests(); }
  [[nodiscard]] std::uint64_t claims_ended() const noexcept { return gate_->claims_ended(); }

 private:
  std::unique_ptr<Gate> gate_;
  std::unique_ptr<DdsDoor> dds_;
  std::unique_ptr<EngineSocket> socket_;
  std::unique_ptr<TeleopLink> link_;
  std::unique_ptr<Ros2Door> ros2_;
};

}  // namespace hapticd::server
