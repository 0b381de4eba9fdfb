#pragma once
// The in-process session API: build a session from a session file or YAML text (with overrides), step it in
// lockstep, read every device's view after a step, feed a device the rendering engine's input, send it every
// request the DDS interface offers, read the loop's statistics. Each step runs the server's own cycle (the same
// function as its real-time loop: read and estimate, group stage, chains, limit and write) on a virtual clock on
// the caller's thread, so a run is repeatable and independent of the machine's speed. Tests, benchmarks and the
// evaluation tool are built on it. Not thread-safe: one thread drives a session.
//
//   hapticd::server::Session s = hapticd::server::Session::from_file("config/sessions/demo.yaml",
//                                                                    {.overrides = {"server.seed=7"}});
//   s.step(2000);  // 1 s at 2 kHz
//   const hapticd::server::DeviceView v = s.device("v3");
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/chain_signals.hpp"
#include "hapticd/device_description.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/export.hpp"
#include "hapticd/runtime_request.hpp"
#include "hapticd/server/device_request.hpp"
#include "hapticd/simulated_truth.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd::server {

struct SessionOptions {
  // Overrides of the session file, applied in order before it is validated: "path=value", the path the keys
  // from the top separated by dots, a device entry by its name; the value YAML. "server.seed=7",
  // "devices.v3.virtual_model.parameters.mass_kg=[2, 2, 2]". An error in an overridden value names the override.
  std::vector<std::string> overrides;
  // Searched for plugins before the session's own plugin_paths.
  std::vector<std::filesystem::path> plugin_paths;
};

// One device after the last step.
struct DeviceView {
  std::string name;
  std::uint64_t cycle = 0;  // the last cycle run (0 before the first step)
  double time_s = 0.0;      // its time on the session's clock
  DeviceState state;        // the device's sample; its joint velocity is the server's one estimate (the chain's)
  Pose handle_pose;         // forward kinematics of the measured joints (world)
  Twist handle_twist;
  Wrench operator_wrench;  // the operator's wrench on the handle (world, at the handle point)
  TaskTarget task;         // what the virtual model rendered this cycle (pose, twist, wrench)
  JointCommand command;    // the torque written (after the safety supervisor)
  std::string scheme;      // the running control scheme
  // "" while running, else the fault that holds it in its safe mode with the device's reason when it gave one
  // ("emergency stop", "device read failed: a drive's speed monitor tripped: ...").
  std::string fault;
  bool at_rest = true;  // the safe mode has reached zero torque (true without a fault)
  double engine_weight = 0.0;
  std::uint64_t faults = 0, recoveries = 0, scheme_switches = 0, refused_switches = 0;
  std::uint64_t saturated_cycles = 0, limited_cycles = 0, render_limited_cycles = 0;
  double thermal_load = 0.0;
  double dissipated_j = 0.0;
  // A simulated device's true state after the last step (DeviceDescription::simulated); empty for hardware.
  std::optional<SimulatedTruth> truth;
};

struct SessionStatistics {
  std::uint64_t cycles = 0;     // cycles run
  double time_s = 0.0;          // the session's clock
  double compute_p50_us = 0.0;  // time one cycle of the group took on this machine (for information: a
  double compute_p99_us = 0.0;  // lockstep session's timing depends on the machine, its results do not)
  double compute_max_us = 0.0;
};

class HAPTICD_API Session {
 public:
  // Throws std::runtime_error when the session cannot be built: a configuration error names the file (or the
  // override), line and key; a plugin that cannot be loaded or configured names itself. Steps run on a virtual
  // clock whatever the session's server.clock says; a dds section starts no DDS interface here.
  static Session from_file(const std::filesystem::path& file, const SessionOptions& options = {});
  // yaml: session-file text; `name` stands for the file in errors, relative paths are taken from the working
  // directory.
  static Session from_yaml(const std::string& yaml, const SessionOptions& options = {},
                           const std::string& name = "<session>");
  Session(Session&&) noexcept;
  Session& operator=(Session&&) noexcept;
  ~Session();  // stops the session (stop()) if it still runs

  [[nodiscard]] std::vector<std::string> device_names() const;
  [[nodiscard]] double period_s() const noexcept;
  [[nodiscard]] std::uint64_t cycles_run() const noexcept;

  // Runs `cycles` cycles. The first step powers the devices; the chains activate in the first cycle.
  void step(std::uint64_t cycles = 1);
  // Throws std::out_of_range for a device the session does not have.
  [[nodiscard]] DeviceView device(std::string_view name) const;
  // What the device plugin said about itself, with the base pose the session file gives it (world frame).
  [[nodiscard]] DeviceDescription description(std::string_view name) const;
  // The rendering engine's input for the device, picked up by the next cycle (as one that came over DDS).
  void set_engine_input(std::string_view device, const EngineInput& input);
  // A run-time request, as a client of the DDS interface would send it (ownership aside: an in-process caller
  // owns every device). The reply says whether it was accepted and why not.
  RuntimeReply request(std::string_view device, const DeviceRequest& request);
  [[nodiscard]] SessionStatistics statistics() const;
  // Ends the session as a run of its duration ends: the torques ramp to zero over server.shutdown_ramp_s (the
  // chains run on meanwhile), then the chains and devices are deactivated. Nothing can be stepped afterwards.
  // Throws std::runtime_error naming each device whose disable() failed and each plugin that threw as it was
  // deactivated (during the run - a scheme left by a fault or a switch - or now; an incomplete friction
  // identification does) - after every device was disabled.
  void stop();

  struct Impl;  // the server's own tests reach the device sessions through it (session/session_impl.hpp)
  [[nodiscard]] Impl& impl() noexcept { return *impl_; }

 private:
  explicit Session(std::unique_ptr<Impl> impl) noexcept;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapticd::server
