#pragma once
// The requests side of a device (docs/architecture.md, "Threads and hand-offs"): everything another thread may
// ask of it - an emergency stop, a recovery, the server's safe stop, the passivity controller on or off, the
// rendering engine's input, another control scheme, and the run-time requests to its plugins (parameters and
// commands). Any thread, never the loop; the loop picks the requests up at its next cycle (DeviceSession reads
// them as a friend). The safety requests are lock-free. The plugin requests are not real-time: they take the
// device's request lock, never held by the loop. apply() carries out a DeviceRequest (hapticd/server/
// device_request.hpp): the DDS interface's request dispatcher and the in-process session both route through it, so
// a request means the same whichever way it comes. Ownership of the device is the caller's check.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "hapticd/engine_input.hpp"
#include "hapticd/runtime_request.hpp"
#include "hapticd/server/device_request.hpp"
#include "loader/plugin_requests.hpp"
#include "session/device_chain.hpp"
#include "session/device_status.hpp"
#include "session/engine_input_port.hpp"
#include "session/scheme_switcher.hpp"

namespace hapticd::server {

class TeleopPhase;

class DeviceRequests {
 public:
  // The parts of its device the requests reach; all outlive this (members of the same DeviceSession).
  DeviceRequests(const std::string& name, DeviceChain& chain, const DeviceStatus& status, SchemeSwitcher& schemes,
                 EngineInputPort& engine) noexcept
      : name_(name), chain_(chain), status_(status), schemes_(schemes), engine_(engine) {}
  DeviceRequests(const DeviceRequests&) = delete;
  DeviceRequests& operator=(const DeviceRequests&) = delete;

  // A DeviceRequest of any kind, answered with what was done or why not.
  RuntimeReply apply(const DeviceRequest& request);

  // Emergency stop: the loop puts the device in its safe state at the next cycle (fault emergency_stop); the
  // session keeps running for the other devices. A stop latches: it cancels every recovery requested before it,
  // and a stop while the device is already safe is a fault of its own (report, log, exit code).
  void emergency_stop() noexcept {
    stop_epoch_.fetch_add(1, std::memory_order_acq_rel);  // first: a recovery asked before this stop is void
    estop_requests_.fetch_add(1, std::memory_order_acq_rel);
  }
  // Leave the safe mode. Refused when there is no fault or the device never configured or never ran; otherwise
  // the loop recovers once the safe mode has settled (the last torque faded out, damping done): the chain
  // activates again from the measured state with a soft start. Only a request made after the last stop counts.
  RuntimeReply recover();
  // The server is stopping (SIGINT/SIGTERM): the device goes through its safe mode - damping, then zero torque -
  // without a fault. DeviceStatus::at_rest() tells when it is done.
  void safe_stop() noexcept { safe_stop_requested_.store(true, std::memory_order_release); }
  [[nodiscard]] bool safe_stopping() const noexcept { return safe_stop_requested_.load(std::memory_order_relaxed); }
  // The passivity controller on or off from the next cycle (the safety stage's run-time switch).
  void passivity_control(bool on) noexcept { passivity_request_.store(on ? 1 : 0, std::memory_order_release); }
  // The rendering engine's newest input; the loop picks it up at the next cycle and stamps it with that cycle's time.
  void engine_input(const EngineInput& input) { engine_.publish(input); }
  // The device's side of a teleoperation link (its transport's face: deliver, take; nullptr: not a link's).
  [[nodiscard]] TeleopPhase* teleoperation() const noexcept { return teleop_; }
  // The engine released the device: its input fades out without the engine counting as stale.
  void end_engine_input() noexcept { engine_.end(); }
  // The control scheme `name` from the next cycle boundary on (scheme_switcher.hpp); false if there is none.
  bool switch_scheme(std::string_view name) { return schemes_.request(name); }

  // The plugin of one stage that takes run-time requests - the device, the running scheme's virtual model, inverse
  // kinematics or controller, or the model of the device's group (shared with the group's other devices).
  // stage_plugin() looks once and pins what it saw: the loop may switch schemes while a request is served, and
  // every scheme's plugins stay configured, so a request acts on the plugin it looked up (its command, the values
  // of its parameters in effect, a run-time set of a tunable parameter already checked against the schema - the
  // plugin's tune() may still refuse it), never on a stage that vanished in between. nullopt: the running scheme
  // has no such stage, or there is no scheme. Requests to one device's plugins are handled one at a time, and
  // never while DeviceSession::service() deactivates a scheme; requests to the group's model one at a time across
  // the group.
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

  // The device the requests go to, as the other threads know it (a consumer that holds this face alone has it).
  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] const DeviceDescription& description() const noexcept { return chain_.description; }
  [[nodiscard]] const DeviceChain& chain() const noexcept { return chain_; }
  [[nodiscard]] const SchemeSwitcher& schemes() const noexcept { return schemes_; }
  [[nodiscard]] const DeviceStatus& status() const noexcept { return status_; }

 private:
  friend class DeviceSession;  // the loop takes the requests; service() and deactivate() take the request lock

  // f(the stage's PluginRequestTarget) under the request lock; nullopt when the plugin has gone.
  template <class F>
  auto with_stage_plugin(const StagePlugin& stage, F&& f)
      -> std::optional<std::invoke_result_t<F, const PluginRequestTarget&>>;

  const std::string& name_;
  DeviceChain& chain_;
  const DeviceStatus& status_;
  SchemeSwitcher& schemes_;
  EngineInputPort& engine_;
  TeleopPhase* teleop_ = nullptr;  // set before the loop runs (DeviceSession::enable_teleoperation)
  // Every stop (an E-stop request, a fault the loop raises) increments stop_epoch_; a recovery request records the
  // epoch it was made in (+1, 0: none) and is carried out only while no stop has come since.
  std::atomic<std::uint64_t> stop_epoch_{0};
  std::atomic<std::uint64_t> estop_requests_{0};
  std::atomic<std::uint64_t> recovery_for_epoch_{0};
  std::atomic<bool> safe_stop_requested_{false};
  std::atomic<int> passivity_request_{-1};  // -1: none, else 0/1
  // One request to this device's plugins, or service(), at a time (never the loop). The monitor's service() skips
  // a round while a request runs, and deactivate() does not wait for good on a request thread that is stuck (a
  // broken invariant parks it: app/invariant_stop) - both with try_lock (a timed lock's clocklock is invisible to
  // ThreadSanitizer).
  std::mutex plugin_requests_;
  SharedPlugin* group_model_ = nullptr;  // the group's model, if the device is in a group that has one
};

}  // namespace hapticd::server
