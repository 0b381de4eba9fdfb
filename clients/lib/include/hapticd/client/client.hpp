#pragma once
// The C++ client library of hapticd's DDS interface (docs/dds-interface.md, "Clients"): find
// devices and groups, read their states, events, telemetry and fault reports, claim a device and send it
// engine commands, make every request with a timeout. One Client is one DDS participant (loopback-only by
// default). Values only: the types of types.hpp, no DDS header.
//
// Threading:
//  - Waiting calls (wait_for_*, every request) block the calling thread up to their timeout; polling calls
//    (devices, latest_*, take_events) return at once. Both may be called from any thread, concurrently.
//  - State and group-state callbacks run on Cyclone's receive thread, one at a time: an engine answers a state
//    from there with no thread wake-up in between. Event, telemetry and fault-report callbacks run on the
//    client's own thread, one at a time. A callback may send commands and poll but must not wait (no request, no
//    wait_for_*), set a callback or destroy the client.
//  - Setting a callback replaces the previous one atomically; once on_*() returns the old one is not called again.
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

#include "hapticd/client/scene_client.hpp"
#include "hapticd/client/types.hpp"
#include "hapticd/parameter_info.hpp"

namespace hapticd::client {

struct ClientOptions {
  ClientOptions(std::string id, int domain = 0) : client_id(std::move(id)), domain_id(domain) {}  // NOLINT

  std::string client_id;  // 1..31 characters, unique per client; the owner name a claim records
  int domain_id = 0;
  std::filesystem::path cyclone_config;  // a Cyclone XML file
  // Else the network: "interfaces=eth1;peers=192.0.2.2;multicast=false" (docs/deployment.md). Neither: the
  // environment's HAPTICD_DDS_CONFIG or HAPTICD_DDS_NETWORK, else the built-in loopback-only configuration.
  std::string network;
  double command_deadline_s = 0.05;  // offered on the command writer: must not exceed the server's deadline
};

struct Reply {
  bool answered = false;  // false: no reply within the timeout
  bool accepted = false;
  std::string message;
  std::vector<double> values;  // get_parameter: the value in effect (a boolean as 0 or 1)
};

// One device's command within a group command (Client::send_group).
struct DeviceCommand {
  Name device;
  EngineCommand command;
};

class HAPTICD_API Client {
 public:
  // Throws std::invalid_argument for a client id out of 1..31 characters, std::runtime_error when the DDS
  // participant cannot be created (the message says why: a bad Cyclone configuration, for example).
  explicit Client(ClientOptions options);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  [[nodiscard]] const std::string& id() const noexcept;

  // ---- devices ----
  [[nodiscard]] std::vector<DeviceInfo> devices() const;  // the descriptions received so far
  // Waits until the device's description arrived; with started, one that carries the start pose (sent again once
  // the server's loop has run its first cycle).
  std::optional<DeviceInfo> wait_for_device(std::string_view device, Timeout timeout, bool started = false);
  [[nodiscard]] std::optional<DeviceState> latest_state(std::string_view device) const;
  // Waits until a state of the device with serial > after arrives.
  std::optional<DeviceState> wait_for_state(std::string_view device, Timeout timeout, std::uint64_t after = 0);

  // ---- device groups (docs/multi-device.md) ----
  [[nodiscard]] std::vector<GroupInfo> groups() const;
  std::optional<GroupInfo> wait_for_group(std::string_view group, Timeout timeout);
  [[nodiscard]] std::optional<GroupState> latest_group_state(std::string_view group) const;
  std::optional<GroupState> wait_for_group_state(std::string_view group, Timeout timeout, std::uint64_t after = 0);

  // ---- events, telemetry, fault reports ----
  // The events received since the last call, oldest first (the newest 1024 are kept between calls).
  std::vector<Event> take_events();
  [[nodiscard]] std::optional<Telemetry> latest_telemetry(std::string_view device) const;
  // The newest fault report of a device (a late joiner gets the newest one per device).
  [[nodiscard]] std::optional<FaultReport> latest_fault_report(std::string_view device) const;

  // ---- callbacks (see Threading above) ----
  void on_state(std::function<void(const DeviceState&)> callback);
  void on_group_state(std::function<void(const GroupState&)> callback);
  // Events are also kept for take_events.
  void on_event(std::function<void(const Event&)> callback);
  void on_telemetry(std::function<void(const Telemetry&)> callback);
  // Reports that arrived before the callback was set are handed to it at once, on the caller's thread.
  void on_fault_report(std::function<void(const FaultReport&)> callback);
  // A claim this client made ended without its release: the server handed the device on or freed it (the
  // claimant seemed gone for longer than the server's claim hold, docs/safety.md). Told once per claim, on the
  // receive thread, when a state names another owner after one that named this client. Claim again or stop.
  void on_claim_lost(std::function<void(std::string_view device, std::string_view reason)> callback);
  // Whether the newest claim of `device` (or of the group holding it) was lost so (reset by a new claim).
  [[nodiscard]] bool claim_lost(std::string_view device) const;

  // ---- requests: the reply, or answered = false after the timeout. A request without a reply is sent again
  // (the same id) every 250 ms until the timeout; the server applies it once and answers each copy. ----
  Reply request(std::string_view device, RequestKind kind, std::string_view name = {},
                const std::vector<double>& values = {}, Timeout timeout = kDefaultTimeout);
  Reply claim(std::string_view device, Timeout timeout = kDefaultTimeout);
  Reply release(std::string_view device, Timeout timeout = kDefaultTimeout);
  Reply switch_scheme(std::string_view device, std::string_view scheme, Timeout timeout = kDefaultTimeout);
  // parameter: "<stage>.<name>", e.g. "virtual_model.mass_kg".
  Reply set_parameter(std::string_view device, std::string_view parameter, const std::vector<double>& values,
                      Timeout timeout = kDefaultTimeout);
  // Any parameter of the stage's plugin (tunable or not) or safety.passivity_control: Reply::values holds it,
  // the message says "name = value" (text parameters only there).
  Reply get_parameter(std::string_view device, std::string_view parameter, Timeout timeout = kDefaultTimeout);
  // A parameter's declaration (type, unit, bounds, run-time tunable, description) and value in effect; info is
  // empty when the reply refused or did not come (reply says why).
  struct ParameterAnswer {
    Reply reply;
    std::optional<ParameterInfo> info;
  };
  ParameterAnswer describe_parameter(std::string_view device, std::string_view parameter,
                                     Timeout timeout = kDefaultTimeout);
  // Every parameter of the device (its plugins' in stage order, then the safety stage's), one request each;
  // reply is the last one (the one that failed, if any).
  struct ParameterList {
    Reply reply;
    std::vector<ParameterInfo> parameters;
  };
  ParameterList parameters(std::string_view device, Timeout timeout = kDefaultTimeout);
  Reply emergency_stop(std::string_view device, Timeout timeout = kDefaultTimeout);
  // Leave the safe mode (accepted when the device is in it; it recovers once at zero torque).
  Reply recover(std::string_view device, Timeout timeout = kDefaultTimeout);
  // Simulated devices: "push" {fx, fy, fz[, ramp_s]}, "move" {dx, dy, dz[, duration_s]}, "grasp" {g}, "release".
  Reply operator_command(std::string_view device, std::string_view command, const std::vector<double>& values = {},
                         Timeout timeout = kDefaultTimeout);
  // Group requests: claim every device of the group or none; release those the client owns; E-stop every
  // device; recover every device (each in its safe mode, free or the client's) or none. Group "*": E-stop or
  // recover every device of every server on the domain.
  Reply claim_group(std::string_view group, Timeout timeout = kDefaultTimeout);
  Reply release_group(std::string_view group, Timeout timeout = kDefaultTimeout);
  Reply emergency_stop_group(std::string_view group, Timeout timeout = kDefaultTimeout);
  Reply recover_group(std::string_view group, Timeout timeout = kDefaultTimeout);

  // ---- engine commands (after a successful claim): false when the command could not be written ----
  bool send(std::string_view device, const EngineCommand& command);
  bool send_coupling(std::string_view device, const Pose& proxy, const Twist& proxy_twist, std::uint64_t state_serial);
  bool send_wrench(std::string_view device, const Wrench& wrench, std::uint64_t state_serial);
  bool send_motion(std::string_view device, const Pose& pose, const Twist& twist, std::uint64_t state_serial);
  // One command for a whole group (after claim_group): one per device, in the group's order.
  bool send_group(std::string_view group, std::span<const DeviceCommand> commands);
  // Restart serial numbers (claim and claim_group do it).
  void reset_serial() noexcept;

  // ---- an engine's world, for the live view (docs/live-view.md) ----
  // Publishes the shapes of the engine's world (at most kMaxWorldShapes; a few tens of times a second is plenty),
  // keyed by this client's id; the servers' live views draw them beside their devices. False when it could not be
  // written (too many shapes, DDS Security does not permit this identity to publish hapticd_world).
  bool publish_world(std::span<const WorldShape> shapes, double time_s = 0.0);

  // ---- the session's haptic scene (docs/haptic-scene.md): claim it, edit it, ask what the hands do to it ----
  // Made on first use, on this client's participant (the scene's claim is this client's); lives as long as it.
  // Throws std::runtime_error when its topics cannot be made (DDS Security: only an identity that may command every
  // device may edit the scene, docs/deployment.md).
  SceneClient& scene();

 private:
  // The devices of a group as its description names them (none before it arrived).
  [[nodiscard]] std::vector<std::string> group_devices(std::string_view group) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapticd::client
