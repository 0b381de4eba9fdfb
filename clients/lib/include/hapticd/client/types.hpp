#pragma once
// The value types of the client library: what the server publishes over DDS (docs/dds-interface.md) as the
// SDK's types (Pose, Twist, Wrench, JointVector), and what a client sends. No DDS header is needed to use them.
// Names are bounded texts held in place (Name): a state is converted without touching the heap.
#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/export.hpp"
#include "hapticd/joint_vector.hpp"
#include "hapticd/spatial.hpp"
#include "hapticd/state_flags.hpp"

namespace hapticd::client {

// How long a waiting call waits (seconds).
using Timeout = std::chrono::duration<double>;
inline constexpr Timeout kDefaultTimeout{2.0};

inline constexpr int kMaxGroupDevices = 8;  // devices per group (the data model's MAX_GROUP_DEVICES)
inline constexpr int kMaxValues = 16;       // values per request or reply
inline constexpr int kRejectReasons = 8;    // Telemetry::rejected's entries

// A name of up to 31 characters, stored in place.
class HAPTICD_API Name {
 public:
  Name() = default;
  Name(std::string_view text) noexcept { assign(text); }  // NOLINT(google-explicit-constructor): a value
  void assign(std::string_view text) noexcept;
  [[nodiscard]] std::string_view view() const noexcept { return {text_.data(), size_}; }
  [[nodiscard]] std::string str() const { return std::string(view()); }
  [[nodiscard]] bool empty() const noexcept { return size_ == 0; }
  operator std::string_view() const noexcept { return view(); }  // NOLINT(google-explicit-constructor)
  friend bool operator==(const Name& a, std::string_view b) noexcept { return a.view() == b; }

 private:
  std::array<char, 32> text_{};
  std::uint8_t size_ = 0;
};

enum class Mode : std::uint8_t { starting, running, stopping, safe, off };
[[nodiscard]] HAPTICD_API std::string_view to_string(Mode mode) noexcept;

// DeviceState::flags and FaultRecord::flags, one bit each: hapticd/state_flags.hpp (state_flag::*) defines them
// for the server, the clients and recordings alike.
enum Flag : std::uint32_t {
  kTorqueSaturated = state_flag::torque_saturated,
  kEngineActive = state_flag::engine_active,
  kEngineStale = state_flag::engine_stale,
  kEstop = state_flag::estop,
  kFault = state_flag::fault,
  kSwitching = state_flag::switching,
  kSafeDamping = state_flag::safe_damping,
  kLimitEngaged = state_flag::limit_engaged,
  kRenderLimited = state_flag::render_limited,
  kThermalDerating = state_flag::thermal_derating,
  kPassivityControl = state_flag::passivity_control
};
// The names of the set flags (hapticd::kStateFlagNames: "torque_saturated", "engine_active", ...), lowest bit
// first; a bit without a name as "bit<i>".
[[nodiscard]] HAPTICD_API std::vector<std::string> flag_names(std::uint32_t flags);

// The loop's health: counts since the start, worst times over the last second.
struct LoopSummary {
  double rate_hz = 0.0;
  std::uint64_t cycles = 0;
  std::uint64_t overruns = 0;
  double latency_max_us = 0.0;
  double compute_max_us = 0.0;
};

struct SchemeInfo {
  std::string name;
  std::string virtual_model;  // the plugin engine commands reach the device through ("" none)
};

// A device's description (sent when a client joins, and again with the start pose after the first cycle).
struct DeviceInfo {
  std::string device;
  int version = 0;  // the server's data model version
  std::string device_plugin;
  bool simulated = false;  // accepts operator commands
  double rate_hz = 0.0;
  int dof = 0;
  std::vector<std::string> joint_names;
  JointVector position_min, position_max, velocity_max;  // rad or m (per second)
  JointVector torque_peak, torque_continuous;            // N m or N
  std::string base_frame;
  Pose base_pose;  // the device's base in the world frame
  std::string handle_frame;
  std::optional<Pose> start_pose;  // the handle at the first cycle; empty before it
  double workspace_radius = 0.0;   // m around the start pose (0: not given)
  Eigen::Vector3d workspace_min = Eigen::Vector3d::Zero(), workspace_max = Eigen::Vector3d::Zero();
  std::vector<SchemeInfo> schemes;
  double command_deadline_s = 0.0;  // engine commands must arrive at least this often
  double command_fade_s = 0.0;      // after a missed deadline the engine's forces fade to zero over this time
  // A handle device (docs/devices.md): its joints are the handle's axes (x, y, z; rx, ry, rz; gripper).
  bool handle_device = false;
  int handle_dof = 0;  // 3 or 6 (orientation sensed); 0 for a joint device
  bool has_gripper = false;
  int button_count = 0;
};

// One published state of a device (world frame; wrenches and twists at the handle point).
struct DeviceState {
  Name device;
  std::uint64_t serial = 0;  // one per published state, increasing
  std::uint64_t cycle = 0;
  std::int64_t loop_time_ns = 0;
  Pose pose;  // measured handle pose
  Twist twist;
  Wrench operator_wrench;     // the operator's wrench on the handle
  Wrench environment_wrench;  // what the rendered environment applies to the handle
  Pose target_pose;           // the chain's desired pose (admittance schemes)
  int dof = 0;
  JointVector position, velocity, torque;  // torque: commanded
  std::uint32_t buttons = 0;               // the handle's buttons, bit i: button i pressed
  double gripper = 0.0;                    // the gripper's opening (rad), 0 without one
  Mode mode = Mode::starting;
  std::uint32_t flags = 0;  // Flag bits
  Name fault;               // "" when none
  Name scheme;
  Name owner;                       // "" when free
  std::uint64_t engine_serial = 0;  // the newest engine command the loop has applied
  LoopSummary loop;

  [[nodiscard]] double time_s() const noexcept { return static_cast<double>(loop_time_ns) * 1e-9; }
};

struct GroupInfo {
  std::string group;
  int version = 0;
  std::vector<std::string> devices;  // in the group's order (GroupState::states in the same)
  double min_distance_m = 0.0;       // hard minimum clearance (0: not checked)
  double repulsion_distance_m = 0.0;
  bool own_loop = false;
};

// Every device of a group from one cycle.
struct GroupState {
  Name group;
  std::uint64_t serial = 0;
  std::uint64_t cycle = 0;
  std::int64_t loop_time_ns = 0;
  double clearance_m = -1.0;  // closest approach of the group's arms this cycle (-1: not measured)
  int device_count = 0;
  std::array<DeviceState, kMaxGroupDevices> states{};  // the first device_count
};

enum class EventKind : std::uint8_t {
  fault,  // the device went to its safe state; code names the fault
  estop,
  mode,
  scheme,           // code: the new scheme
  owner,            // code: the new owner ("" released)
  engine_stale,     // the owner missed the command deadline; forces fade
  engine_rejected,  // a command was rejected (rate-limited)
  recovered,        // the device left its safe mode on request
  recording,        // the session's recording failed
  parameter         // a parameter was set at run time; code: its plugin slot, message: "<name> = <values> ..."
};
[[nodiscard]] HAPTICD_API std::string_view to_string(EventKind kind) noexcept;

struct Event {
  std::string device;
  std::uint64_t serial = 0;
  std::int64_t loop_time_ns = 0;
  EventKind kind = EventKind::mode;
  std::string code;
  std::string message;
};

// Ten times a second per device.
struct Telemetry {
  std::string device;
  std::int64_t wall_time_ns = 0;
  LoopSummary loop;
  std::uint64_t states_published = 0, commands_received = 0, commands_accepted = 0;
  // Rejected commands by reason: malformed, non-finite, out of bounds, out of order, stale, not the owner,
  // wrong kind for the scheme, other.
  std::array<std::uint64_t, kRejectReasons> rejected{};
  std::uint64_t requests = 0, deadline_misses = 0, scheme_switches = 0;
  std::uint64_t saturated_cycles = 0, limited_cycles = 0, render_limited_cycles = 0;
  std::uint64_t faults = 0, recoveries = 0;
  double thermal_load = 0.0;  // largest joint thermal load (1: continuous torque for ever)
  double dissipated_j = 0.0;  // energy the passivity controller dissipated
};

// One cycle before a fault.
struct CycleRecord {
  std::uint64_t cycle = 0;
  std::int64_t loop_time_ns = 0;
  JointVector position, velocity, torque;  // torque: written
  Eigen::Vector3d handle_position = Eigen::Vector3d::Zero(), handle_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator_force = Eigen::Vector3d::Zero(), environment_force = Eigen::Vector3d::Zero();
  std::uint32_t flags = 0;  // Flag bits the safety layer sets: torque saturated, limit engaged, render limited, thermal
};

// A fault and the cycles before it (oldest first).
struct FaultReport {
  std::string device;
  std::uint64_t serial = 0;  // per device, one per fault
  std::string fault;
  std::string message;
  std::uint64_t cycle = 0;
  std::int64_t loop_time_ns = 0;
  int dof = 0;
  std::vector<CycleRecord> records;
};

// ---- what a client sends ----
enum class CommandKind : std::uint8_t {
  wrench,    // impedance type: a wrench, optionally with a local linear model
  coupling,  // impedance type: a proxy pose (and twist) for the virtual coupling
  motion     // admittance type: the desired motion of the handle
};

// WRENCH with a local model: every cycle until the next command the server applies
// wrench + stiffness .* (anchor - x) - damping .* xd.
struct LocalModel {
  Pose anchor;
  Eigen::Matrix<double, 6, 1> stiffness = Eigen::Matrix<double, 6, 1>::Zero();  // N/m (3), N m/rad (3)
  Eigen::Matrix<double, 6, 1> damping = Eigen::Matrix<double, 6, 1>::Zero();    // N s/m (3), N m s/rad (3)
};

struct HAPTICD_API EngineCommand {
  CommandKind kind = CommandKind::coupling;
  std::uint64_t state_serial = 0;  // the state it answers (0: none)
  Wrench wrench;                   // wrench
  std::optional<LocalModel> local_model;
  Pose pose;    // coupling: the proxy; motion: the desired pose
  Twist twist;  // coupling: the proxy's twist; motion: the desired twist

  [[nodiscard]] static EngineCommand coupling(const Pose& proxy, const Twist& proxy_twist, std::uint64_t state_serial);
  [[nodiscard]] static EngineCommand force(const Wrench& wrench, std::uint64_t state_serial);
  [[nodiscard]] static EngineCommand motion(const Pose& pose, const Twist& twist, std::uint64_t state_serial);
};

// ---- an engine's world, for the live view (Client::publish_world; docs/live-view.md) ----
inline constexpr int kMaxWorldShapes = 64;
enum class ShapeKind : std::uint8_t { box, sphere, capsule, cylinder, ellipsoid, plane };
struct WorldShape {
  Name body;  // the body it belongs to ("world": fixed)
  ShapeKind kind = ShapeKind::box;
  // box, ellipsoid: half-extents (semi-axes) along the pose's x, y, z; sphere: x the radius; capsule, cylinder: x the
  // radius, y half the length along the pose's z; plane: x, y half-extents (0: unbounded), the normal the pose's z.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Eigen::Vector4d color = Eigen::Vector4d::Ones();  // red, green, blue, alpha in 0..1
  Pose pose;                                        // world frame
};

enum class RequestKind : std::uint8_t {
  claim,
  release,
  switch_scheme,
  set_parameter,
  estop,
  operator_command,
  describe,
  recover,
  get_parameter,
  group_claim,
  group_release,
  group_estop,
  group_recover,
  describe_parameter
};

}  // namespace hapticd::client
