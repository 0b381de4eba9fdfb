#pragma once
// The C++ client library of hapticd's DDS interface (docs/dds-interface.md): connect, find devices by name,
// receive their state, events and telemetry through typed callbacks, claim a device and send it engine
// commands, and make requests with a timeout. One Client is one DDS participant (loopback-only by default).
//
// Callbacks run one at a time: state callbacks on Cyclone's receive thread (no extra thread wake-up between a
// state's arrival and the engine's answer), the others on the client's own thread. A callback may send
// commands (an engine answers each state from its state callback) but must not wait for a reply, set a
// callback or destroy the client.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/spatial.hpp"
#include "hapticd_msg.h"

namespace hapticd::client {

struct ClientOptions {
  std::string client_id;  // unique per client; the owner name a claim records
  int domain_id = 0;
  std::filesystem::path cyclone_config;  // empty: the built-in loopback-only configuration
  double command_deadline_s = 0.05;      // offered on the command writer: must not exceed the server's deadline
};

struct Reply {
  bool answered = false;  // false: no reply within the timeout
  bool accepted = false;
  std::string message;
  std::vector<double> values;  // get_parameter: the value in effect (a boolean as 0 or 1)
};

using Timeout = std::chrono::duration<double>;

class Client {
 public:
  explicit Client(ClientOptions options);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  [[nodiscard]] const std::string& id() const noexcept;

  // ---- discovery ----
  // The descriptions received so far (one per device).
  [[nodiscard]] std::vector<hapticd_msg_DeviceDescription> devices() const;
  // Waits until the named device's description arrived; with started, one that carries the start pose (sent
  // again once the server's loop has run its first cycle).
  std::optional<hapticd_msg_DeviceDescription> wait_for_device(std::string_view device, Timeout timeout,
                                                               bool started = false);
  // The newest state of a device, if any arrived.
  [[nodiscard]] std::optional<hapticd_msg_DeviceState> latest_state(std::string_view device) const;
  // Waits until a state of the device with serial > after arrives.
  std::optional<hapticd_msg_DeviceState> wait_for_state(std::string_view device, Timeout timeout,
                                                        std::uint64_t after = 0);

  // ---- device groups (docs/multi-device.md) ----
  // The group descriptions received so far, and waiting for one.
  [[nodiscard]] std::vector<hapticd_msg_GroupDescription> groups() const;
  std::optional<hapticd_msg_GroupDescription> wait_for_group(std::string_view group, Timeout timeout);
  // The newest group state (every device's state from one cycle; about 7 kB, hence on the heap), nullptr if none.
  [[nodiscard]] std::unique_ptr<hapticd_msg_GroupState> latest_group_state(std::string_view group) const;
  // Waits until a group state with serial > after arrives.
  std::unique_ptr<hapticd_msg_GroupState> wait_for_group_state(std::string_view group, Timeout timeout,
                                                               std::uint64_t after = 0);

  // ---- callbacks (set before the data flows; replaced atomically) ----
  void on_state(std::function<void(const hapticd_msg_DeviceState&)> callback);
  // Group states, on Cyclone's receive thread like on_state (an engine of a group answers from here).
  void on_group_state(std::function<void(const hapticd_msg_GroupState&)> callback);
  void on_event(std::function<void(const hapticd_msg_Event&)> callback);
  void on_telemetry(std::function<void(const hapticd_msg_Telemetry&)> callback);
  // A device's fault and the cycles before it (a late joiner gets the newest one per device). Reports that
  // arrived before the callback was set are handed to it at once, on the caller's thread.
  void on_fault_report(std::function<void(const hapticd_msg_FaultReport&)> callback);
  // The newest fault report of a device received so far (a copy: about 100 kB), nullptr if none.
  [[nodiscard]] std::unique_ptr<hapticd_msg_FaultReport> latest_fault_report(std::string_view device) const;

  // ---- requests ----
  Reply request(std::string_view device, hapticd_msg_RequestKind kind, std::string_view name = {},
                const std::vector<double>& values = {}, Timeout timeout = std::chrono::seconds(2));
  Reply claim(std::string_view device, Timeout timeout = std::chrono::seconds(2));
  Reply release(std::string_view device, Timeout timeout = std::chrono::seconds(2));
  Reply switch_scheme(std::string_view device, std::string_view scheme, Timeout timeout = std::chrono::seconds(2));
  // parameter: "<stage>.<name>", e.g. "virtual_model.mass_kg".
  Reply set_parameter(std::string_view device, std::string_view parameter, const std::vector<double>& values,
                      Timeout timeout = std::chrono::seconds(2));
  // Any parameter of the stage's plugin (tunable or not) or safety.passivity_control: Reply::values holds it,
  // the message says "name = value" (text parameters only there).
  Reply get_parameter(std::string_view device, std::string_view parameter, Timeout timeout = std::chrono::seconds(2));
  Reply emergency_stop(std::string_view device, Timeout timeout = std::chrono::seconds(2));
  // Leave the safe mode (accepted when the device is in it; it recovers once at zero torque).
  Reply recover(std::string_view device, Timeout timeout = std::chrono::seconds(2));
  // Group requests: claim every device of the group or none; release those the client owns; E-stop every
  // device; recover every device (each in its safe mode, free or the client's) or none. Group "*": E-stop or
  // recover every device of every server on the domain.
  Reply claim_group(std::string_view group, Timeout timeout = std::chrono::seconds(2));
  Reply release_group(std::string_view group, Timeout timeout = std::chrono::seconds(2));
  Reply emergency_stop_group(std::string_view group, Timeout timeout = std::chrono::seconds(2));
  Reply recover_group(std::string_view group, Timeout timeout = std::chrono::seconds(2));
  // Simulated devices: "push" {fx, fy, fz[, ramp_s]} or "release".
  Reply operator_command(std::string_view device, std::string_view command, const std::vector<double>& values = {},
                         Timeout timeout = std::chrono::seconds(2));

  // ---- engine commands (after a successful claim) ----
  // Fills device, engine id and the next serial number, then writes. state_serial: the state it answers.
  bool send(std::string_view device, hapticd_msg_EngineCommand& command);
  bool send_coupling(std::string_view device, const Pose& proxy, const Twist& proxy_twist, std::uint64_t state_serial);
  bool send_wrench(std::string_view device, const Wrench& wrench, std::uint64_t state_serial);
  bool send_motion(std::string_view device, const Pose& pose, const Twist& twist, std::uint64_t state_serial);
  // One command for a whole group (after claim_group): one per device, in the group's order, each with its
  // device's name and the device state it answers (coupling_command makes a coupling one). Fills the engine id
  // and the serials. Writes one GroupCommand; false if it cannot.
  bool send_group(std::string_view group, std::span<hapticd_msg_EngineCommand> commands);
  // Restart serial numbers (a new claim after a release).
  void reset_serial() noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A coupling command for one device of a group command (Client::send_group).
[[nodiscard]] hapticd_msg_EngineCommand coupling_command(std::string_view device, const Pose& proxy,
                                                         const Twist& proxy_twist, std::uint64_t state_serial);

// Conversions from the wire types.
[[nodiscard]] std::string_view name_of(const hapticd_msg_Name& name) noexcept;
[[nodiscard]] std::string_view name_of(const hapticd_msg_Text& text) noexcept;
[[nodiscard]] Pose pose_of(const hapticd_msg_Pose& pose) noexcept;
[[nodiscard]] Twist twist_of(const double (&twist)[6]) noexcept;
[[nodiscard]] Wrench wrench_of(const double (&wrench)[6]) noexcept;

}  // namespace hapticd::client
