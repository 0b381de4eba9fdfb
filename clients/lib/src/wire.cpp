#include "wire.hpp"

#include <algorithm>

#include "hapticd/dds/conversion.hpp"

namespace hapticd::client::wire {

namespace {

using dds::text_of;

// A count from the wire, within [0, limit].
int bounded(std::int32_t count, int limit) noexcept { return std::clamp<int>(count, 0, limit); }

Eigen::Vector3d vector3(const double (&in)[3]) noexcept { return {in[0], in[1], in[2]}; }
bool valid_quaternion(const double (&q)[4]) noexcept {
  return q[0] != 0.0 || q[1] != 0.0 || q[2] != 0.0 || q[3] != 0.0;
}

// One field from its DDS form (the generated copies below call these).
template <class T>
void get(T in, T& out) noexcept {
  out = in;
}
template <std::size_t N>
void get(const char (&in)[N], Name& out) noexcept {
  out.assign(text_of(in));
}
template <std::size_t N>
void get(const char (&in)[N], std::string& out) {
  out = text_of(in);
}
void get(const hapticd_msg_Pose& in, Pose& out) noexcept { out = dds::to_pose(in); }
void get(const double (&in)[6], Twist& out) noexcept { out = Twist{{in[0], in[1], in[2]}, {in[3], in[4], in[5]}}; }
void get(const double (&in)[6], Wrench& out) noexcept { out = Wrench{{in[0], in[1], in[2]}, {in[3], in[4], in[5]}}; }
void get(const double (&in)[3], Eigen::Vector3d& out) noexcept { out = vector3(in); }
template <class T, class U, std::size_t N>
void get(const T (&in)[N], std::array<U, N>& out) noexcept {
  std::copy(std::begin(in), std::end(in), out.begin());
}
void get(hapticd_msg_DeviceMode in, Mode& out) noexcept {
  out = in >= hapticd_msg_MODE_STARTING && in <= hapticd_msg_MODE_OFF ? static_cast<Mode>(in) : Mode::off;
}
void get(hapticd_msg_EventKind in, EventKind& out) noexcept {
  out =
      in >= hapticd_msg_EVENT_FAULT && in <= hapticd_msg_EVENT_PARAMETER ? static_cast<EventKind>(in) : EventKind::mode;
}
void get_joints(const double (&in)[hapticd_msg_MAX_JOINTS], int dof, JointVector& out) noexcept {
  out.resize(dof);
  for (int i = 0; i < dof; ++i) out[i] = in[i];
}

#include "hapticd_wire/from_msg.inc"

static_assert(static_cast<int>(Mode::off) == hapticd_msg_MODE_OFF);
static_assert(static_cast<int>(EventKind::recording) == hapticd_msg_EVENT_RECORDING);
static_assert(static_cast<int>(EventKind::parameter) == hapticd_msg_EVENT_PARAMETER);
static_assert(static_cast<int>(CommandKind::motion) == hapticd_msg_COMMAND_MOTION);
static_assert(static_cast<int>(RequestKind::describe_parameter) == hapticd_msg_REQUEST_DESCRIBE_PARAMETER);
static_assert(kMaxGroupDevices == hapticd_msg_MAX_GROUP_DEVICES && kMaxValues == hapticd_msg_MAX_VALUES &&
              kRejectReasons == hapticd_msg_REJECT_REASONS && kMaxJoints == hapticd_msg_MAX_JOINTS);

}  // namespace

// Each message: its generated field copies, then the fields whose shapes differ between DDS and C++ (the table's
// custom ones).
DeviceInfo from_msg(const hapticd_msg_DeviceDescription& in) {
  DeviceInfo d;
  copy_fields(in, d);
  for (int i = 0; i < d.dof; ++i) d.joint_names.emplace_back(text_of(in.joint_names[i].text));
  if (valid_quaternion(in.start_pose.orientation)) d.start_pose = dds::to_pose(in.start_pose);
  for (int k = 0; k < bounded(in.scheme_count, hapticd_msg_MAX_SCHEMES); ++k)
    d.schemes.push_back(
        {std::string(text_of(in.schemes[k].text)), std::string(text_of(in.scheme_virtual_model[k].text))});
  return d;
}

void from_msg(const hapticd_msg_DeviceState& in, DeviceState& out) noexcept { copy_fields(in, out); }

GroupInfo from_msg(const hapticd_msg_GroupDescription& in) {
  GroupInfo g;
  copy_fields(in, g);
  for (int k = 0; k < bounded(in.device_count, kMaxGroupDevices); ++k)
    g.devices.emplace_back(text_of(in.devices[k].text));
  return g;
}

void from_msg(const hapticd_msg_GroupState& in, GroupState& out) noexcept {
  copy_fields(in, out);
  for (int k = 0; k < out.device_count; ++k) from_msg(in.states[k], out.states[static_cast<std::size_t>(k)]);
}

Event from_msg(const hapticd_msg_Event& in) {
  Event e;
  copy_fields(in, e);
  return e;
}

Telemetry from_msg(const hapticd_msg_Telemetry& in) {
  Telemetry t;
  copy_fields(in, t);
  return t;
}

FaultReport from_msg(const hapticd_msg_FaultReport& in) {
  FaultReport r;
  copy_fields(in, r);
  const int count = bounded(in.record_count, hapticd_msg_MAX_HISTORY);
  r.records.resize(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    CycleRecord& c = r.records[static_cast<std::size_t>(k)];
    copy_fields(in.records[k], c);
    // A record's joints are the report's (its dof).
    get_joints(in.records[k].position, r.dof, c.position);
    get_joints(in.records[k].velocity, r.dof, c.velocity);
    get_joints(in.records[k].torque, r.dof, c.torque);
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
