#pragma once
// The session file: server settings, and per device its plugin chain. Plugin parameters stay YAML here; they
// are checked against each plugin's own schema once the plugin is loaded (session/session_builder).
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "config/config_overrides.hpp"
#include "config/repulsion_settings.hpp"
#include "config/ros2_settings.hpp"
#include "config/teleoperation_settings.hpp"
#include "hapticd/dds/network.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/spatial.hpp"
#include "safety/safety_settings.hpp"

namespace hapticd::server {

// realtime: the loops sleep to absolute deadlines on the monotonic clock; lockstep: a virtual clock, as fast as
// possible; device: the session's loop runs one cycle per tick of a device whose SDK owns the servo loop.
enum class ClockMode { realtime, lockstep, device };
[[nodiscard]] const char* clock_name(ClockMode mode) noexcept;
[[nodiscard]] ClockMode clock_mode(const std::string& name);  // one of the names above (validated before)

struct ServerSettings {
  double rate_hz = 2000.0;
  ClockMode clock = ClockMode::realtime;
  std::string clock_device;  // clock: device - the device whose ticks clock the loop ("": the one that can)
  int clock_line = 0;        // where `clock` stands in the file (0: not given)
  double duration_s = 0.0;   // 0: until SIGINT/SIGTERM
  std::uint64_t seed = 1;
  int realtime_priority = 80;  // SCHED_FIFO priority; 0: do not ask
  bool lock_memory = true;
  int cpu = -1;                                     // pin the loop thread to this CPU; -1: no pinning
  int cpu_dma_latency_us = 0;                       // PM QoS limit held by a real-time loop; -1: left alone
  double shutdown_ramp_s = 0.2;                     // torques ramp to zero over this time at the end of a session
  std::vector<std::filesystem::path> plugin_paths;  // resolved against the session file's folder
};

// The `dds` section: the DDS interface (docs/dds-interface.md). Absent: no DDS participant is created.
// The gate's settings (docs/architecture.md, "The gate and its doors"): what every door's commands must satisfy,
// how long a claim outlives its claimant, how often states and telemetry go out, lockstep. The `gate` section;
// a session without one may give these keys in its `dds` section (as before the gate had a section of its own).
struct GateSettings {
  double state_rate_hz = 0.0;  // 0: every cycle
  double telemetry_rate_hz = 10.0;
  double max_sample_age_s = 0.1;  // commands older than this (source timestamp) are rejected
  double max_force_n = 300.0;     // bounds of accepted engine commands
  double max_torque_nm = 30.0;
  double max_stiffness_n_per_m = 20000.0;
  double max_rotational_stiffness_n_m_per_rad = 200.0;
  double max_damping_n_s_per_m = 500.0;
  double max_rotational_damping_n_m_s = 5.0;
  double max_distance_m = 2.0;  // proxy, anchor and motion poses within this distance of the device base
  double max_speed_m_s = 5.0;
  double max_angular_speed_rad_s = 20.0;
  bool lockstep_sync = true;           // lockstep clock: each cycle waits for the owning engine's answer
  double lockstep_wait_s = 0.5;        // ... at most this long (wall time), then stops waiting for that engine
  double lockstep_start_wait_s = 0.0;  // lockstep: the first cycle waits this long (wall) for an engine to answer
  // ... for an engine on every device (a two-engine run starts with both answering: repeatable), or on any.
  bool lockstep_start_every = true;
  // A claim whose peer shows no sign of life (no live command writer, no open connection) this long after the
  // claim ends (the claimant cannot be watched; docs/safety.md).
  double claim_grace_s = 0.5;
  // A claimant that is still there but has shown no sign of life this long (a frozen or killed process; a VR
  // application loading a scene or collecting garbage is frozen for a second or so) loses its claim. Its forces
  // fade at the command deadline all the same (docs/safety.md, "Ownership").
  double claim_hold_s = 5.0;
  // Who may set a claimed device's tunable parameters (not safety.*): its owner only, or anyone (a console tuning
  // the coupling while an engine runs; the owner hears of every set as a parameter event and may set it back).
  bool tuning_by_anyone = false;
};

// The `dds` section: the DDS door (docs/dds-interface.md). Absent: none.
struct DdsSettings {
  bool enabled = false;
  int domain_id = 0;
  std::filesystem::path cyclone_config;  // empty: the built-in loopback configuration
  // `dds.network` (not with cyclone_config): interfaces, unicast peers, multicast - docs/deployment.md. Neither:
  // HAPTICD_DDS_CONFIG or HAPTICD_DDS_NETWORK from the environment, else loopback only.
  std::optional<dds::NetworkSettings> network;
  // CPU of the DDS threads (the bridge's and Cyclone's): -2 auto (real-time clock on 2+ CPUs: the loop gets
  // the last CPU unless server.cpu says otherwise, the DDS threads the others), -1 no pinning, else that CPU.
  int cpu = -2;
  // Writers whose participant the server remembers (for ownership) and writers that lost their liveliness: a
  // bounded table, least recently used first out (docs/safety.md, "Ownership").
  int max_peers = 256;
  // Cyclone DDS's own log lines pass through the server's logger at most this often (the rest are counted).
  double log_lines_per_s = 5.0;
};

// The `live_view` section: the Foxglove WebSocket live view (docs/live-view.md). Absent: none.
struct LiveViewSettings {
  bool enabled = false;
  std::string address = "127.0.0.1";  // the interface it listens on (loopback by default)
  int port = 8765;                    // 0: any free port (the log says which)
  double rate_hz = 30.0;              // messages per channel and second
  int max_clients = 4;
  double force_scale_m_per_n = 0.005;  // length of the wrench arrows in the 3-D view
  // Web pages that may connect besides those served from this machine (their Origin: "https://host[:port]").
  std::vector<std::string> allowed_origins;
};

// The `engine_socket` section: the WebSocket/JSON door to the DDS interface's gate for clients without DDS
// (docs/engine-socket.md). Absent: none. Needs the `dds` section.
struct EngineSocketSettings {
  bool enabled = false;
  std::string address = "127.0.0.1";  // loopback by default; another address needs a token
  int port = 8766;                    // 0: any free port (the log says which)
  std::string token;                  // read from token_file ("": none, loopback only)
  // TLS (wss://): a PEM certificate chain and its private key, both or neither (paths resolved).
  std::filesystem::path tls_certificate_file, tls_private_key_file;
  int max_clients = 4;
  double max_messages_per_s = 5000.0;  // per client: more are dropped (counted, the client told)
  std::vector<std::string> allowed_origins;
};

struct PluginConfig {
  std::string plugin;
  std::optional<std::string> library;
  YAML::Node parameters;  // validated later against the plugin's schema
  std::string key_path;   // "devices[0].controller"
  int line = 0;
};

// A control scheme: the plugin chain between the device's reading and its torques.
struct SchemeConfig {
  std::string name;
  std::optional<PluginConfig> virtual_model;
  std::optional<PluginConfig> inverse_kinematics;
  PluginConfig controller;
};

// A collision capsule given in the session file: around the segment from-to in the link's frame.
struct CapsuleConfig {
  std::string link;
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  Eigen::Vector3d to = Eigen::Vector3d::Zero();
  double radius_m = 0.0;
  std::string key_path;  // "devices[0].collision.capsules[1]"
  int line = 0;
};

// A device's collision geometry (`collision`): the capsules given here replace the URDF's <collision> elements;
// without either, capsules along the kinematic skeleton of this radius cover the links.
struct CollisionConfig {
  std::vector<CapsuleConfig> capsules;
  double skeleton_radius_m = 0.03;
};

// A device group (`groups`): its devices share one loop instant and its group stage (docs/multi-device.md).
struct GroupConfig {
  std::string name;
  std::vector<std::string> devices;
  double min_distance_m = 0.0;  // the hard minimum between any two of its devices' capsules; 0: no check
  RepulsionSettings repulsion;
  // `loop`: the group runs on a loop thread of its own (in real time; lockstep runs every loop on one thread),
  // pinned to loop_cpu (-1: not pinned). Without it the group runs on the session's loop.
  bool own_loop = false;
  int loop_cpu = -1;
  std::optional<PluginConfig> model;  // `model`: the group's model (bimanual coupling: shared_object)
  std::string key_path;               // "groups[0]"
  int line = 0;
};

struct DeviceConfig {
  std::string name;
  PluginConfig device;
  // The scheme the device starts with (the device entry's own virtual_model / inverse_kinematics / controller,
  // named by its `scheme` key, "default" if absent).
  std::optional<PluginConfig> virtual_model;
  std::optional<PluginConfig> inverse_kinematics;
  PluginConfig controller;
  std::string scheme = "default";
  // Alternatives the device can switch to at run time (`schemes` list), configured at start-up.
  std::vector<SchemeConfig> alternatives;
  double switch_ramp_s = 0.1;       // a torque difference at a switch fades out over this time
  double engine_deadline_s = 0.05;  // engine input older than this fades out ...
  double engine_fade_s = 0.02;      // ... over this time
  double engine_ramp_in_s = 0.1;    // engine input starting after a silence ramps in over this time
  SafetySettings safety;            // the `safety` section (docs/safety.md)
  Pose base_pose;                   // the device's base in the session's world frame (`base_pose`)
  CollisionConfig collision;        // the `collision` section
};

struct SessionConfig {
  std::filesystem::path file;
  ServerSettings server;
  DdsSettings dds;
  GateSettings gate;  // the `gate` section, or the gate's keys in the `dds` section
  LiveViewSettings live_view;
  EngineSocketSettings engine_socket;
  TeleoperationSettings teleoperation;
  Ros2Settings ros2;
  // The session's haptic scene (`scene`; docs/haptic-scene.md): its plugin (session_scene unless named) and its
  // parameters (the scene file). None without the section.
  std::optional<PluginConfig> scene;
  std::vector<DeviceConfig> devices;
  std::vector<GroupConfig> groups;
  std::vector<AppliedOverride> overrides;  // what overrides changed: an error there names the override
  std::vector<std::string> warnings;       // safety functions the session turns off: said at start-up
};

// The keys of a device entry (`devices[i]`) and what each is: the reader's allowed keys and
// hapticd --describe-config print this one list.
struct EntryKey {
  const char* key;
  const char* text;
};
const std::vector<EntryKey>& device_entry_keys();

// The schema of the `server` section: validates it and documents it (hapticd --describe-config).
ParameterSchema server_settings_schema();
// The schema of the `dds` section.
ParameterSchema dds_settings_schema();
// The `gate` section's keys (also accepted in the `dds` section).
ParameterSchema gate_settings_schema(const GateSettings& defaults = {});
// The schema of the `live_view` section.
ParameterSchema live_view_settings_schema();
// The schema of the `engine_socket` section.
ParameterSchema engine_socket_settings_schema();
// The `base_pose` of a device entry.
ParameterSchema base_pose_schema();
// The schema of a group's `repulsion` mapping.
ParameterSchema repulsion_schema();
// The schema of a group's `loop` mapping.
ParameterSchema group_loop_schema();

// Reads and validates a session file, with overrides ("path=value", config/config_overrides.hpp) applied first.
// Throws ConfigError naming file, line and key (or the override).
SessionConfig load_session_config(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});
// The same for session-file text; `file` names it in errors and relative paths are taken from its folder.
SessionConfig parse_session_config(const std::string& text, const std::filesystem::path& file,
                                   const std::vector<std::string>& overrides = {});

}  // namespace hapticd::server
