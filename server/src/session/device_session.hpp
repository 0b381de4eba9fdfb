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
#include "session/device_snapshot.hpp"
#include "session/device_status.hpp"
#include "session/engine_input_port.hpp"
#include "session/scheme_switcher.hpp"
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
  // Not real-time safe. Zero torque, chain off, device disabled (brakes engaged). A disable() that throws is
  // caught, so the caller goes on to disable the other devices, and kept in disable_error(); a plugin whose
  // deactivate() throws does not keep the device from being disabled (take_plugin_errors()).
  void deactivate();
  // Why the last deactivate() could not disable the device cleanly; empty if it could.
  [[nodiscard]] const std::string& disable_error() const noexcept { return disable_error_; }

  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] const DeviceDescription& description() const noexcept { return description_; }
  [[nodiscard]] const DeviceChain& chain() const noexcept { return chain_; }
  // Readable from any thread.
  [[nodiscard]] DeviceFault fault() const noexcept { return status_.fault.load(std::memory_order_acquire); }
  // Any thread: the device's reason for the fault (or for a refused fault reset), nullptr if it gave none.
  [[nodiscard]] const char* fault_reason() const noexcept {
    return status_.fault_reason.load(std::memory_order_relaxed);
  }
  // Any thread: the fault as a sentence with the device's reason ("device read failed: joint 2 ..."); "" if none.
  [[nodiscard]] std::string fault_text() const;
  [[nodiscard]] std::uint64_t refused_recoveries() const noexcept {
    return status_.refused_recoveries.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t fault_cycle() const noexcept {
    return status_.fault_cycle.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t saturated_cycles() const noexcept {
    return status_.saturated_cycles.load(std::memory_order_relaxed);
  }
  // Loop thread only (or after the loop has stopped).
  [[nodiscard]] const DeviceState& state() const noexcept { return state_; }
  [[nodiscard]] const JointCommand& command() const noexcept { return command_; }
  [[nodiscard]] const TaskTarget& task() const noexcept { return task_; }
  [[nodiscard]] const ChainState& chain_state() const noexcept { return estimator_.state(); }
  [[nodiscard]] double engine_weight() const noexcept { return engine_.input().weight; }

  // Any thread: the control schemes - request another, the one running, the switches made or refused.
  [[nodiscard]] SchemeSwitcher& schemes() noexcept { return schemes_; }
  [[nodiscard]] const SchemeSwitcher& schemes() const noexcept { return schemes_; }
  // Any thread (the DDS interface): the rendering engine's newest input; the loop picks it up at the next cycle
  // and stamps it with that cycle's time.
  void publish_engine_input(const EngineInput& input) { engine_.publish(input); }
  // Any thread: the engine released the device; its input fades out without the engine counting as stale.
  void end_engine_input() noexcept { engine_.end(); }
  // Any thread: the newest snapshot the loop published (see set_snapshot_interval); false if none since the
  // last take. One reader at a time.
  bool take_snapshot(DeviceSnapshot& out) noexcept { return status_.snapshots.take(out); }
  // Before activate(): the loop publishes a snapshot every `cycles` cycles (0: never, the default).
  void set_snapshot_interval(std::uint64_t cycles) noexcept { snapshot_interval_ = cycles; }
  // The live view's snapshots (its own hand-off, at its own interval: the two readers never take each other's).
  bool take_view_snapshot(DeviceSnapshot& out) noexcept { return status_.view_snapshots.take(out); }
  void set_view_interval(std::uint64_t cycles) noexcept { view_interval_ = cycles; }
  // Before activate(): build the snapshot every cycle (the recorder reads it), publishing still at the interval.
  void set_snapshot_every_cycle(bool on) noexcept { snapshot_every_cycle_ = on; }
  // Loop thread: the snapshot built at the newest published cycle (a group's stage gathers its devices'), or
  // of this cycle with set_snapshot_every_cycle.
  [[nodiscard]] const DeviceSnapshot& published_snapshot() const noexcept { return snapshot_; }
  // Loop thread: the engine input in effect this cycle.
  // Any thread: emergency stop. The loop puts the device in its safe state at the next cycle (fault
  // emergency_stop); the session keeps running for the other devices. A stop latches: it cancels every
  // recovery requested before it, and a stop while the device is already safe is a fault of its own (report,
  // log, exit code).
  void request_emergency_stop() noexcept {
    stop_epoch_.fetch_add(1, std::memory_order_acq_rel);  // first: a recovery asked before this stop is void
    estop_requests_.fetch_add(1, std::memory_order_acq_rel);
  }
  // The loop thread, in the group stage (phase (b)): a fault the device's group found (two arms closer than the
  // group's hard minimum). The device enters its safe mode this cycle; ignored when it is there already.
  void raise_group_fault(DeviceFault fault, const CycleTime& cycle, const char* reason) noexcept;
  // The loop thread, in the group stage: another device of the group near this one. The nearest of the cycle
  // reaches the chain (ChainState::neighbour).
  void offer_neighbour(const NeighbourClearance& neighbour) noexcept;
  // The loop thread, in the group stage: a force on the handle (world, N) from the group this cycle (the arms'
  // repulsion), rendered with the safety supervisor's own.
  void add_group_force(const Eigen::Vector3d& force) noexcept { group_force_ += force; }
  // Any thread: the server is stopping (SIGINT/SIGTERM): the device goes through its safe mode - damping,
  // then zero torque - without a fault. at_rest() tells when it is done.
  void request_safe_stop() noexcept { safe_stop_requested_.store(true, std::memory_order_release); }
  [[nodiscard]] bool safe_stopping() const noexcept { return safe_stop_requested_.load(std::memory_order_relaxed); }
  // Any thread: leave the safe mode. Refused when there is no fault or the device never configured; otherwise
  // the loop recovers once the safe mode has settled (the last torque faded out, damping done): the chain
  // activates again from the measured state with a soft start. Only a request made after the last stop counts.
  RuntimeReply request_recovery();
  // Any thread (the monitor): the next fault or recovery from the device's log, oldest first; false if none.
  // One reader. The loop counts what did not fit (lost_safety_events).
  bool take_safety_event(SafetyEvent& out) noexcept { return status_.safety_events.try_pop(out); }
  [[nodiscard]] std::uint64_t lost_safety_events() const noexcept {
    return status_.lost_safety_events.load(std::memory_order_relaxed);
  }
  // Any thread: the safe mode has reached zero torque (or there is no fault).
  [[nodiscard]] bool at_rest() const noexcept { return status_.at_rest.load(std::memory_order_acquire); }
  // Any thread: the newest fault report (the fault and the cycles before it); false if none since the last take.
  // One reader at a time.
  bool take_fault_report(FaultReport& out) noexcept { return status_.reports.take(out); }
  [[nodiscard]] std::uint64_t faults_raised() const noexcept { return status_.faults.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t recoveries() const noexcept { return status_.recoveries.load(std::memory_order_relaxed); }
  // Any thread: counters and gauges of the safety supervisor.
  [[nodiscard]] std::uint64_t limited_cycles() const noexcept {
    return status_.limited_cycles.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t render_limited_cycles() const noexcept {
    return status_.render_limited_cycles.load(std::memory_order_relaxed);
  }
  [[nodiscard]] double dissipated_j() const noexcept { return status_.dissipated_j.load(std::memory_order_relaxed); }
  [[nodiscard]] double thermal_load() const noexcept { return status_.thermal_load.load(std::memory_order_relaxed); }
  // Loop thread only (tests): the supervisor.
  [[nodiscard]] const SafetySupervisor& safety() const noexcept { return safety_; }
  // Any thread: the passivity controller on or off from the next cycle (the safety stage's run-time switch).
  void request_passivity_control(bool on) noexcept { passivity_request_.store(on ? 1 : 0, std::memory_order_release); }
  // Any thread: the passivity controller is on (as of the last cycle).
  [[nodiscard]] bool passivity_control() const noexcept {
    return status_.passivity_control.load(std::memory_order_acquire);
  }
  // Not real-time safe, not the loop thread (device_requests routes here): the plugin of one stage that takes
  // run-time requests - the device, the running scheme's virtual model, inverse kinematics or controller, or the
  // model of the device's group (shared with the group's other devices). stage_plugin() looks once and pins what
  // it saw: the loop may switch schemes while a request is
  // served, and every scheme's plugins stay configured, so a request acts on the plugin it looked up (its
  // command, the values of its parameters in effect, a run-time set of a tunable parameter already checked
  // against the schema - the plugin's tune() may still refuse it), never on a stage that vanished in between.
  // nullopt: the running scheme has no such stage, or there is no scheme. Requests to one device's plugins are
  // handled one at a time, and never while service() deactivates a scheme; requests to the group's model one at a
  // time across the group.
  enum class Stage : std::uint8_t { device, virtual_model, inverse_kinematics, controller, group_model };
  struct StagePlugin {
    Stage stage;
    std::size_t scheme;  // the scheme's index (unused for the device)
    const PluginDescriptor* descriptor;
  };
  [[nodiscard]] std::optional<StagePlugin> stage_plugin(Stage stage) const;
  RuntimeReply plugin_request(const StagePlugin& stage, std::string_view name, const std::vector<double>& values);
  // The values in effect; nullopt when the plugin left in between (a group's model deactivated at the end).
  [[nodiscard]] std::optional<Parameters> stage_parameters(const StagePlugin& stage);
  RuntimeReply tune(const StagePlugin& stage, const std::string& name, ParameterValue value);
  // Before the loop runs (the group stage): the model of the device's group, which its requests reach.
  void set_group_model(SharedPlugin* model) noexcept { group_model_ = model; }
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
  [[nodiscard]] const SchemeChain* running_scheme() const noexcept {
    return chain_.schemes.empty() ? nullptr : &chain_.schemes[schemes_.active_index()];
  }
  // f(PluginInstance<T>&) on the pinned stage's plugin (stage_plugin() found it: schemes never lose a stage).
  template <class F>
  // f(the stage's PluginRequestTarget) under the request lock; nullopt when the plugin has gone.
  auto with_stage_plugin(const StagePlugin& stage, F&& f)
      -> std::optional<std::invoke_result_t<F, const PluginRequestTarget&>>;
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
  DeviceSnapshot snapshot_;
  std::uint64_t snapshot_interval_ = 0;
  std::uint64_t view_interval_ = 0;
  bool snapshot_every_cycle_ = false;
  // E-stops and recoveries (any thread -> loop). Every stop (an E-stop request, a fault the loop raises)
  // increments stop_epoch_; a recovery request records the epoch it was made in (+1, 0: none) and is carried
  // out only while no stop has come since.
  std::atomic<std::uint64_t> stop_epoch_{0};
  std::atomic<std::uint64_t> estop_requests_{0};
  std::uint64_t estops_handled_ = 0;  // loop thread
  std::atomic<std::uint64_t> recovery_for_epoch_{0};
  // After a scheme switch or a recovery: the torque the drives held fades out against the chain's commands.
  TorqueBlend blend_;

  // Safety.
  SafetySupervisor safety_;
  FaultReport report_;
  std::atomic<bool> safe_stop_requested_{false};
  bool stopped_ = false;                    // loop thread: the safe stop has begun
  std::atomic<int> passivity_request_{-1};  // -1: none, else 0/1
  std::string disable_error_;
  // One request to this device's plugins, or service(), at a time (never the loop). The monitor's service()
  // skips a round while a request runs, and deactivate() does not wait for good on a request thread that is
  // stuck (a broken invariant parks it: app/invariant_stop) - both with try_lock (a timed lock's clocklock is
  // invisible to ThreadSanitizer).
  std::mutex plugin_requests_;
  SharedPlugin* group_model_ = nullptr;  // the group's model, if the device is in a group that has one
  // This cycle (phase (a) -> (c) -> (d)): the safe-mode step instead of the chain; the measurement can be trusted.
  bool safe_path_ = false;
  bool measurement_valid_ = false;
  JointVector last_written_;  // the last torque the device accepted
};

}  // namespace hapticd::server
