#include "wire.hpp"

#include <algorithm>

#include "hapticd/dds/conversion.hpp"

namespace hapticd::client::wire {

namespace {

using dds::text_of;

// A count from the wire, within [0, limit].
int bounded(std::int32_t count, int limit) noexcept { return std::clamp<int>(count, 0, limit); }

JointVector joints(const double (&in)[hapticd_msg_MAX_JOINTS], int dof) {
  JointVector v(dof);
  for (int i = 0; i < dof; ++i) v[i] = in[i];
  return v;
}
void joints(const double (&in)[hapticd_msg_MAX_JOINTS], int dof, JointVector& out) noexcept {
  out.resize(dof);
  for (int i = 0; i < dof; ++i) out[i] = in[i];
}
Eigen::Vector3d vector3(const double (&in)[3]) noexcept { return {in[0], in[1], in[2]}; }
Twist twist(const double (&in)[6]) noexcept { return Twist{{in[0], in[1], in[2]}, {in[3], in[4], in[5]}}; }
Wrench wrench(const double (&in)[6]) noexcept { return Wrench{{in[0], in[1], in[2]}, {in[3], in[4], in[5]}}; }
LoopSummary loop(const hapticd_msg_LoopSummary& in) noexcept {
  return {in.rate_hz, in.cycles, in.overruns, in.latency_max_us, in.compute_max_us};
}
Mode mode(hapticd_msg_DeviceMode in) noexcept {
  return in >= hapticd_msg_MODE_STARTING && in <= hapticd_msg_MODE_OFF ? static_cast<Mode>(in) : Mode::off;
}
bool valid_quaternion(const double (&q)[4]) noexcept {
  return q[0] != 0.0 || q[1] != 0.0 || q[2] != 0.0 || q[3] != 0.0;
}

static_assert(static_cast<int>(Mode::off) == hapticd_msg_MODE_OFF);
static_assert(static_cast<int>(EventKind::recording) == hapticd_msg_EVENT_RECORDING);
static_assert(static_cast<int>(EventKind::parameter) == hapticd_msg_EVENT_PARAMETER);
static_assert(static_cast<int>(CommandKind::motion) == hapticd_msg_COMMAND_MOTION);
static_assert(static_cast<int>(RequestKind::describe_parameter) == hapticd_msg_REQUEST_DESCRIBE_PARAMETER);
static_assert(kMaxGroupDevices == hapticd_msg_MAX_GROUP_DEVICES && kMaxValues == hapticd_msg_MAX_VALUES &&
              kRejectReasons == hapticd_msg_REJECT_REASONS && kMaxJoints == hapticd_msg_MAX_JOINTS);

}  // namespace

DeviceInfo from_msg(const hapticd_msg_DeviceDescription& in) {
  DeviceInfo d;
  d.device = text_of(in.device);
  d.version = in.data_model_version;
  d.device_plugin = text_of(in.device_plugin);
  d.simulated = in.simulated;
  d.rate_hz = in.rate_hz;
  d.dof = bounded(in.dof, kMaxJoints);
  for (int i = 0; i < d.dof; ++i) d.joint_names.emplace_back(text_of(in.joint_names[i].text));
  d.position_min = joints(in.position_min, d.dof);
  d.position_max = joints(in.position_max, d.dof);
  d.velocity_max = joints(in.velocity_max, d.dof);
  d.torque_peak = joints(in.torque_peak, d.dof);
  d.torque_continuous = joints(in.torque_continuous, d.dof);
  d.base_frame = text_of(in.base_frame);
  d.base_pose = dds::to_pose(in.base_pose);
  d.handle_frame = text_of(in.handle_frame);
  if (valid_quaternion(in.start_pose.orientation)) d.start_pose = dds::to_pose(in.start_pose);
  d.workspace_radius = in.workspace_radius;
  d.workspace_min = vector3(in.workspace_min);
  d.workspace_max = vector3(in.workspace_max);
  for (int k = 0; k < bounded(in.scheme_count, hapticd_msg_MAX_SCHEMES); ++k)
    d.schemes.push_back(
        {std::string(text_of(in.schemes[k].text)), std::string(text_of(in.scheme_virtual_model[k].text))});
  d.command_deadline_s = in.command_deadline_s;
  d.command_fade_s = in.command_fade_s;
  d.handle_device = in.handle_device;
  d.handle_dof = bounded(in.handle_dof, 6);
  d.has_gripper = in.has_gripper;
  d.button_count = bounded(in.button_count, 32);
  return d;
}

void from_msg(const hapticd_msg_DeviceState& in, DeviceState& out) noexcept {
  out.device.assign(text_of(in.device));
  out.serial = in.serial;
  out.cycle = in.cycle;
  out.loop_time_ns = in.loop_time_ns;
  out.pose = dds::to_pose(in.handle_pose);
  out.twist = twist(in.twist);
  out.operator_wrench = wrench(in.operator_wrench);
  out.environment_wrench = wrench(in.environment_wrench);
  out.target_pose = dds::to_pose(in.target_pose);
  out.dof = bounded(in.dof, kMaxJoints);
  joints(in.position, out.dof, out.position);
  joints(in.velocity, out.dof, out.velocity);
  joints(in.torque, out.dof, out.torque);
  out.buttons = in.buttons;
  out.gripper = in.gripper;
  out.mode = mode(in.mode);
  out.flags = in.flags;
  out.fault.assign(text_of(in.fault));
  out.scheme.assign(text_of(in.scheme));
  out.owner.assign(text_of(in.owner));
  out.engine_serial = in.engine_serial;
  out.loop = loop(in.loop);
}

GroupInfo from_msg(const hapticd_msg_GroupDescription& in) {
  GroupInfo g;
  g.group = text_of(in.group);
  g.version = in.data_model_version;
  for (int k = 0; k < bounded(in.device_count, kMaxGroupDevices); ++k)
    g.devices.emplace_back(text_of(in.devices[k].text));
  g.min_distance_m = in.min_distance_m;
  g.repulsion_distance_m = in.repulsion_distance_m;
  g.own_loop = in.own_loop;
  return g;
}

void from_msg(const hapticd_msg_GroupState& in, GroupState& out) noexcept {
  out.group.assign(text_of(in.group));
  out.serial = in.serial;
  out.cycle = in.cycle;
  out.loop_time_ns = in.loop_time_ns;
  out.clearance_m = in.clearance_m;
  out.device_count = bounded(in.device_count, kMaxGroupDevices);
  for (int k = 0; k < out.device_count; ++k) from_msg(in.states[k], out.states[static_cast<std::size_t>(k)]);
}

Event from_msg(const hapticd_msg_Event& in) {
  const auto kind = in.kind >= hapticd_msg_EVENT_FAULT && in.kind <= hapticd_msg_EVENT_PARAMETER
                        ? static_cast<EventKind>(in.kind)
                        : EventKind::mode;
  return Event{std::string(text_of(in.device)), in.serial, in.loop_time_ns, kind, std::string(text_of(in.code)),
               std::string(text_of(in.message))};
}

Telemetry from_msg(const hapticd_msg_Telemetry& in) {
  Telemetry t;
  t.device = text_of(in.device);
  t.wall_time_ns = in.wall_time_ns;
  t.loop = loop(in.loop);
  t.states_published = in.states_published;
  t.commands_received = in.commands_received;
  t.commands_accepted = in.commands_accepted;
  std::copy(std::begin(in.rejected), std::end(in.rejected), t.rejected.begin());
  t.requests = in.requests;
  t.deadline_misses = in.deadline_misses;
  t.scheme_switches = in.scheme_switches;
  t.saturated_cycles = in.saturated_cycles;
  t.limited_cycles = in.limited_cycles;
  t.render_limited_cycles = in.render_limited_cycles;
  t.faults = in.faults;
  t.recoveries = in.recoveries;
  t.thermal_load = in.thermal_load;
  t.dissipated_j = in.dissipated_j;
  return t;
}

FaultReport from_msg(const hapticd_msg_FaultReport& in) {
  FaultReport r;
  r.device = text_of(in.device);
  r.serial = in.serial;
  r.fault = text_of(in.fault);
  r.message = text_of(in.message);
  r.cycle = in.cycle;
  r.loop_time_ns = in.loop_time_ns;
  r.dof = bounded(in.dof, kMaxJoints);
  const int count = bounded(in.record_count, hapticd_msg_MAX_HISTORY);
  r.records.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    const hapticd_msg_CycleRecord& c = in.records[k];
    r.records.push_back(CycleRecord{c.cycle, c.loop_time_ns, joints(c.position, r.dof), joints(c.velocity, r.dof),
                                    joints(c.torque, r.dof), vector3(c.handle_position), vector3(c.handle_velocity),
                                    vector3(c.operator_force), vector3(c.environment_force), c.flags});
  }
  return r;
}

void to_msg(const EngineCommand& in, std::string_view device, hapticd_msg_EngineCommand& out) noexcept {
  out = hapticd_msg_EngineCommand{};
  dds::set_text(out.device, device);
  out.kind = static_cast<hapticd_msg_CommandKind>(in.kind);
  out.state_serial = in.state_serial;
  dds::to_msg(in.wrench, out.wrench);
  out.local_model = in.local_model.has_value();
  if (in.local_model) {
    dds::to_msg(in.local_model->anchor, out.anchor);
    dds::to_msg(in.local_model->stiffness, out.stiffness);
    dds::to_msg(in.local_model->damping, out.damping);
  } else {
    out.anchor.orientation[0] = 1.0;
  }
  dds::to_msg(in.pose, out.command_pose);
  dds::to_msg(in.twist, out.twist);
}

hapticd_msg_RequestKind to_msg(RequestKind kind) noexcept { return static_cast<hapticd_msg_RequestKind>(kind); }

}  // namespace hapticd::client::wire
