#pragma once
// One device and its plugin chain: device.read -> virtual model -> inverse kinematics -> controller ->
// safety supervisor -> device.write, once per cycle. Every plugin output is checked (return code, finite, no
// exception) before it can reach a motor; the safety supervisor (safety/safety_supervisor.hpp) limits the
// torques and watches the device. A fault puts this device, and only this device, in its safe mode (joint
// damping, then zero torque) until a recovery is requested; the loop copies the last cycles into a fault report.
//
// Control schemes: the chain between reading and torques can be one of several schemes, all configured at
// start-up. request_scheme() (any thread) asks for another; the loop switches at the next cycle boundary:
// the new scheme's plugins activate from the current state and the last torque command (bumpless transfer),
// and whatever torque difference remains between the old command and the new scheme's first one fades out
// linearly over switch_ramp_s. A scheme that fails to activate is not switched to (the old one keeps
// running; the rejection is counted). The old scheme's plugins are deactivated off the loop by service().
//
// Three faces, one per kind of thread (docs/architecture.md, "Threads and hand-offs"): this class's own methods
// are the loop's (activate, the cycle's phases, the group stage's calls, deactivate) and the monitor's (service);
// status() is what the loop tells the other threads (DeviceStatus: fault, counters, snapshots, reports; read-only
// but for its outlets); requests() is everything another thread may ask of the device (DeviceRequests: stops,
// recovery, engine input, schemes, plugin requests). A consumer holds the face it needs, not the session.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "hapticd/chain_state.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/plugin.hpp"
#include "hapticd/realtime/latest_value.hpp"
#include "hapticd/realtime/spsc_ring.hpp"
#include "loader/plugin_loader.hpp"
#include "loader/plugin_requests.hpp"
#include "safety/device_fault.hpp"
#include "safety/fault_history.hpp"
#include "safety/safety_supervisor.hpp"
#include "session/chain_state_estimator.hpp"
#include "session/device_chain.hpp"
#include "session/device_requests.hpp"
#include "session/device_snapshot.hpp"
#include "session/device_status.hpp"
#include "session/engine_input_port.hpp"
#include "session/scheme_switcher.hpp"
#include "session/teleop_phase.hpp"
#include "session/torque_blend.hpp"

namespace hapticd::server {

class DeviceSession {
 public:
  // The device must be configured (its description is read here); the other plugins configured too.
  DeviceSession(std::string name, DeviceChain chain);
  DeviceSession(const DeviceSession&) = delete;
  DeviceSession& operator=(const DeviceSession&) = delete;

  // Not real-time safe. Enables the device (and homes it if it needs it); the chain activates in the first cycle
  // from the first sample. A device that cannot be enabled or homed is held in its safe state with the reason.
  void activate() noexcept;

  // Real-time safe: one cycle in phases (docs/architecture.md, "One cycle"). The executor runs each phase for
  // every device of a group before the next phase, so the chains of a group see their devices' states of the
  // same instant.
  // (a) Read the device; the watchdogs (E-stop, overruns, a stall: lateness_ns is how late the loop woke, the
  //     server's stop); check the measurement; estimate the chain state (model terms, the one joint velocity).
  void read_and_estimate(const CycleTime& cycle, std::uint32_t consecutive_overruns = 0,
                         std::int64_t lateness_ns = 0) noexcept;
  // (c) The chain - virtual model, inverse kinematics, controller - unless the device is in its safe mode.
  void run_chain(const CycleTime& cycle) noexcept;
  // (d) Limit and write the torque (or the safe mode's torque; torque_scale in [0, 1] ramps the output down at
  //     a planned end), keep the cycle in the history and publish the snapshot.
  void limit_and_write(const CycleTime& cycle, double torque_scale) noexcept;
  // The three phases for this device alone.
  void cycle(const CycleTime& cycle, double torque_scale, std::uint32_t consecutive_overruns = 0,
             std::int64_t lateness_ns = 0) noexcept {
    read_and_estimate(cycle, consecutive_overruns, lateness_ns);
    run_chain(cycle);
    limit_and_write(cycle, torque_scale);
  }
  // Not real-time safe, before the loop runs: the device is one side of a teleoperation link - its port runs in the
  // cycle after the estimate (session/teleop_phase.hpp); its transport reaches it through requests().teleoperation().
  // Throws std::invalid_argument for bad link settings.
  void enable_teleoperation(teleop::Role role, const teleop::LinkSettings& settings);
  // Not real-time safe. Zero torque, chain off, device disabled (brakes engaged). A disable() that throws is
  // caught, so the caller goes on to disable the other devices, and kept in disable_error(); a plugin whose
  // deactivate() throws does not keep the device from being disabled (take_plugin_errors()).
  void deactivate();
  // Why the last deactivate() could not disable the device cleanly; empty if it could.
  [[nodiscard]] const std::string& disable_error() const noexcept { return disable_error_; }

  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] const DeviceDescription& description() const noexcept { return description_; }
  [[nodiscard]] const DeviceChain& chain() const noexcept { return chain_; }
  // The device's other threads (docs/architecture.md, "Threads and hand-offs"): what the loop tells them (any
  // thread reads; each take_* outlet has one reader), and what they may ask of it (any thread but the loop).
  [[nodiscard]] const DeviceStatus& status() const noexcept { return status_; }
  [[nodiscard]] DeviceStatus& status() noexcept { return status_; }
  [[nodiscard]] DeviceRequests& requests() noexcept { return requests_; }
  // Any thread: the scheme running, the switches made or refused (a switch is asked through requests()).
  [[nodiscard]] const SchemeSwitcher& schemes() const noexcept { return schemes_; }

  // Loop thread only (or after the loop has stopped).
  [[nodiscard]] const DeviceState& state() const noexcept { return state_; }
  [[nodiscard]] const JointCommand& command() const noexcept { return command_; }
  [[nodiscard]] const TaskTarget& task() const noexcept { return task_; }
  [[nodiscard]] const ChainState& chain_state() const noexcept { return estimator_.state(); }
  [[nodiscard]] double engine_weight() const noexcept { return engine_.input().weight; }

  // Before activate(): the loop publishes a snapshot every `cycles` cycles (0: never, the default).
  void set_snapshot_interval(std::uint64_t cycles) noexcept { snapshot_interval_ = cycles; }
  // Before activate(): the live view's snapshots at their own interval.
  void set_view_interval(std::uint64_t cycles) noexcept { view_interval_ = cycles; }
  // Before activate(): build the snapshot every cycle (the recorder reads it), publishing still at the interval.
  void set_snapshot_every_cycle(bool on) noexcept { snapshot_every_cycle_ = on; }
  // Loop thread: the snapshot built at the newest published cycle (a group's stage gathers its devices'), or
  // of this cycle with set_snapshot_every_cycle.
  [[nodiscard]] const DeviceSnapshot& published_snapshot() const noexcept { return snapshot_; }
  // The loop thread, in the group stage (phase (b)): a fault the device's group found (two arms closer than the
  // group's hard minimum). The device enters its safe mode this cycle; ignored when it is there already.
  void raise_group_fault(DeviceFault fault, const CycleTime& cycle, const char* reason) noexcept;
  // The loop thread, in the group stage: another device of the group near this one. The nearest of the cycle
  // reaches the chain (ChainState::neighbour).
  void offer_neighbour(const NeighbourClearance& neighbour) noexcept;
  // The loop thread, in the group stage: a force on the handle (world, N) from the group this cycle (the arms'
  // repulsion), rendered with the safety supervisor's own.
  void add_group_force(const Eigen::Vector3d& force) noexcept { group_force_ += force; }
  // Loop thread only (tests): the supervisor.
  [[nodiscard]] const SafetySupervisor& safety() const noexcept { return safety_; }
  // Not real-time safe, not the loop thread: deactivates schemes the loop has left. Call it now and then
  // (the executor's monitor does; a round while a request is served is skipped); deactivate() does it too.
  void service();
  // The thread that calls service() and deactivate(): what the chain's plugins threw as they were deactivated
  // since the last call ("scheme 's', controller 'c': what"). They were taken out all the same.
  [[nodiscard]] std::vector<std::string> take_plugin_errors() { return schemes_.take_errors(); }

 private:
  // The device's description, checked (joints, peak torques, a scheme, the period); throws std::invalid_argument.
  static const DeviceDescription& checked(const std::string& name, const DeviceChain& chain);
  // A fault: report, log, counters, the stop epoch (voids pending recoveries).
  void publish_fault(DeviceFault fault, const CycleTime& cycle, const char* reason = nullptr) noexcept;
  // A fault that puts the device in its safe mode: this cycle takes the safe-mode step in phase (d).
  void raise_fault(DeviceFault fault, const CycleTime& cycle, const char* reason = nullptr) noexcept;
  // Before the first cycle (enable or homing failed): the device never runs; its loop keeps it in the safe state.
  void hold_before_start(DeviceFault fault, const char* reason) noexcept;
  void leave_chain() noexcept;
  [[nodiscard]] SchemeChain* running_scheme() noexcept { return chain_.schemes.empty() ? nullptr : &schemes_.active(); }
  // Phase (a)'s estimate; the chain restarts from the measured state when it (re)activates.
  void estimate(const CycleTime& cycle) noexcept;
  // Phase (c)'s work; plugins may throw despite the contract: caught by run_chain.
  // A fault of the chain and why (a plugin's Outcome::reason, or the server's text; null: none given).
  struct ChainFault {
    DeviceFault fault = DeviceFault::none;
    const char* reason = nullptr;
  };
  ChainFault chain_step(const CycleTime& cycle);
  // Phase (d) in the safe mode: damping (and gravity hold) while the measurement can be trusted, then zero.
  void safe_mode_step(const CycleTime& cycle) noexcept;
  // The command to the device as it takes it: joint torques, or a handle device's newtons and newton-metres
  // (hapticd/handle.hpp: its axes' efforts). What the device threw is its failure.
  Outcome write_device(const CycleTime& cycle) noexcept;
  void recover_if_requested(const CycleTime& cycle) noexcept;
  void record_history(const CycleTime& cycle) noexcept;
  void log_safety_event(SafetyEvent::Kind kind, DeviceFault fault, const CycleTime& cycle) noexcept;
  void relatch_emergency_stop(const CycleTime& cycle) noexcept;
  Outcome activate_scheme(SchemeChain& scheme) noexcept;
  void switch_scheme_if_requested() noexcept;
  void publish_snapshot(const CycleTime& cycle, double torque_scale) noexcept;

  std::string name_;
  DeviceChain chain_;
  DeviceDescription description_;
  ChainStateEstimator estimator_;  // phase (a): the chain state of the cycle
  DeviceStatus status_;            // what the loop tells the other threads
  EngineInputPort engine_;         // phase (c): the engine's input, weighted by its age

  DeviceState state_;
  TaskTarget task_;
  JointTarget joint_target_;
  JointCommand command_;
  Eigen::Vector3d group_force_ = Eigen::Vector3d::Zero();  // phase (b) -> (c): the group's force of this cycle
  bool chain_active_ = false;

  SchemeSwitcher schemes_;
  DeviceRequests requests_;  // what the other threads ask of the loop
  DeviceSnapshot snapshot_;
  std::uint64_t snapshot_interval_ = 0;
  std::uint64_t view_interval_ = 0;
  bool snapshot_every_cycle_ = false;
  std::unique_ptr<TeleopPhase> teleop_;  // the device's side of a teleoperation link, if it is one
  bool ending_ = false;                  // the last cycle's torque was ramped down (the session's planned end)
  std::uint64_t estops_handled_ = 0;     // loop thread: the E-stop requests seen
  // After a scheme switch or a recovery: the torque the drives held fades out against the chain's commands.
  TorqueBlend blend_;

  // Safety.
  SafetySupervisor safety_;
  FaultReport report_;
  bool stopped_ = false;  // loop thread: the safe stop has begun
  bool braked_ = false;   // loop thread: brake(true) was called at rest in the safe mode
  std::string disable_error_;
  // This cycle (phase (a) -> (c) -> (d)): the safe-mode step instead of the chain; the measurement can be trusted.
  bool safe_path_ = false;
  bool measurement_valid_ = false;
  JointVector last_written_;  // the last torque the device accepted
};

}  // namespace hapticd::server
