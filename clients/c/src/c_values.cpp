#include "c_values.hpp"

#include <algorithm>
#include <array>
#include <type_traits>

namespace hapticd::client_c {
namespace {

// The C enums mirror the library's by value (converted with a cast below): held here.
static_assert(static_cast<int>(client::Mode::off) == HAPTICD_MODE_OFF &&
              static_cast<int>(client::Mode::safe) == HAPTICD_MODE_SAFE);
static_assert(static_cast<int>(client::EventKind::fault) == HAPTICD_EVENT_FAULT &&
              static_cast<int>(client::EventKind::owner) == HAPTICD_EVENT_OWNER &&
              static_cast<int>(client::EventKind::recording) == HAPTICD_EVENT_RECORDING &&
              static_cast<int>(client::EventKind::parameter) == HAPTICD_EVENT_PARAMETER);
static_assert(client::kMaxGroupDevices == HAPTICD_MAX_GROUP_DEVICES && client::kMaxValues == HAPTICD_MAX_VALUES &&
              client::kRejectReasons == HAPTICD_REJECT_REASONS && kMaxJoints == HAPTICD_MAX_JOINTS);

hapticd_vec3 vec3(const Eigen::Vector3d& v) noexcept { return hapticd_vec3{v.x(), v.y(), v.z()}; }
Eigen::Vector3d vec3(const hapticd_vec3& v) noexcept { return {v.x, v.y, v.z}; }

template <std::size_t N>
void copy_joints(double (&out)[N], const JointVector& in) noexcept {
  const auto n = static_cast<std::size_t>(std::min<Eigen::Index>(in.size(), N));
  for (std::size_t i = 0; i < N; ++i) out[i] = i < n ? in[static_cast<Eigen::Index>(i)] : 0.0;
}

// One field into its C form (the generated copies below call these).
template <class T>
void put(const T& in, T& out) noexcept {
  out = in;
}
void put(bool in, std::int32_t& out) noexcept { out = in ? 1 : 0; }
template <class E, std::enable_if_t<std::is_enum_v<E>, int> = 0>
void put(E in, std::int32_t& out) noexcept {
  out = static_cast<std::int32_t>(in);
}
template <std::size_t N>
void put(const client::Name& in, char (&out)[N]) noexcept {
  copy_text(out, in.view());
}
template <std::size_t N>
void put(const std::string& in, char (&out)[N]) noexcept {
  copy_text(out, in);
}
void put(const Pose& in, hapticd_pose& out) noexcept;
void put(const Twist& in, hapticd_twist& out) noexcept;
void put(const Wrench& in, hapticd_wrench& out) noexcept;
void put(const Eigen::Vector3d& in, hapticd_vec3& out) noexcept { out = vec3(in); }
void put(const JointVector& in, double (&out)[HAPTICD_MAX_JOINTS]) noexcept { copy_joints(out, in); }
template <std::size_t N>
void put(const std::array<std::uint64_t, N>& in, std::uint64_t (&out)[N]) noexcept {
  std::copy(in.begin(), in.end(), out);
}

}  // namespace

void to_c(const Pose& in, hapticd_pose& out) noexcept {
  out.position = vec3(in.position);
  out.orientation = hapticd_quat{in.orientation.w(), in.orientation.x(), in.orientation.y(), in.orientation.z()};
}
void to_c(const Twist& in, hapticd_twist& out) noexcept { out = hapticd_twist{vec3(in.linear), vec3(in.angular)}; }
void to_c(const Wrench& in, hapticd_wrench& out) noexcept { out = hapticd_wrench{vec3(in.force), vec3(in.torque)}; }

Pose from_c(const hapticd_pose& in) noexcept {
  Pose p;
  p.position = vec3(in.position);
  p.orientation = Eigen::Quaterniond(in.orientation.w, in.orientation.x, in.orientation.y, in.orientation.z);
  return p;
}
Twist from_c(const hapticd_twist& in) noexcept { return Twist{vec3(in.linear), vec3(in.angular)}; }
Wrench from_c(const hapticd_wrench& in) noexcept { return Wrench{vec3(in.force), vec3(in.torque)}; }

namespace {
void put(const Pose& in, hapticd_pose& out) noexcept { to_c(in, out); }
void put(const Twist& in, hapticd_twist& out) noexcept { to_c(in, out); }
void put(const Wrench& in, hapticd_wrench& out) noexcept { to_c(in, out); }

#include "hapticd_wire/to_c.inc"
}  // namespace

void to_c(const client::DeviceState& in, hapticd_device_state& out) noexcept { copy_fields(in, out); }

void to_c(const client::DeviceInfo& in, hapticd_device_info& out) noexcept {
  out = hapticd_device_info{};
  copy_fields(in, out);
  for (std::size_t i = 0; i < in.joint_names.size() && i < HAPTICD_MAX_JOINTS; ++i)
    copy_text(out.joint_names[i], in.joint_names[i]);
  out.has_start_pose = in.start_pose ? 1 : 0;
  if (in.start_pose) to_c(*in.start_pose, out.start_pose);
  out.scheme_count = static_cast<std::int32_t>(std::min<std::size_t>(in.schemes.size(), HAPTICD_MAX_SCHEMES));
  for (std::size_t i = 0; i < static_cast<std::size_t>(out.scheme_count); ++i)
    copy_fields(in.schemes[i], out.schemes[i]);
}

void to_c(const client::GroupInfo& in, hapticd_group_info& out) noexcept {
  out = hapticd_group_info{};
  copy_fields(in, out);
  out.device_count = static_cast<std::int32_t>(std::min<std::size_t>(in.devices.size(), HAPTICD_MAX_GROUP_DEVICES));
  for (std::size_t i = 0; i < static_cast<std::size_t>(out.device_count); ++i) copy_text(out.devices[i], in.devices[i]);
}

void to_c(const client::GroupState& in, hapticd_group_state& out) noexcept {
  copy_fields(in, out);
  out.device_count = std::clamp(in.device_count, 0, HAPTICD_MAX_GROUP_DEVICES);
  for (int i = 0; i < out.device_count; ++i)
    to_c(in.states[static_cast<std::size_t>(i)], out.states[static_cast<std::size_t>(i)]);
}

void to_c(const client::Event& in, hapticd_event& out) noexcept { copy_fields(in, out); }

void to_c(const client::Telemetry& in, hapticd_telemetry& out) noexcept { copy_fields(in, out); }

void to_c(const client::SceneObject& in, hapticd_scene_object& out) noexcept { copy_fields(in, out); }

void to_c(const client::SceneContact& in, hapticd_scene_contact& out) noexcept { copy_fields(in, out); }

void to_c(const client::FaultReport& in, hapticd_fault_report& out) noexcept {
  copy_fields(in, out);
  // The newest records, oldest first.
  const std::size_t n = std::min<std::size_t>(in.records.size(), HAPTICD_MAX_FAULT_RECORDS);
  const std::size_t first = in.records.size() - n;
  out.record_count = static_cast<std::int32_t>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const client::CycleRecord& r = in.records[first + i];
    hapticd_fault_cycle& c = out.records[i];
    copy_fields(r, c);
    copy_joints(c.position, r.position);
    copy_joints(c.velocity, r.velocity);
    copy_joints(c.torque, r.torque);
  }
}

void to_c(const client::Reply& in, hapticd_reply& out) noexcept {
  out.answered = in.answered ? 1 : 0;
  out.accepted = in.accepted ? 1 : 0;
  copy_text(out.message, in.message);
  out.value_count = static_cast<std::int32_t>(std::min<std::size_t>(in.values.size(), HAPTICD_MAX_VALUES));
  for (std::size_t i = 0; i < HAPTICD_MAX_VALUES; ++i)
    out.values[i] = i < static_cast<std::size_t>(out.value_count) ? in.values[i] : 0.0;
}

void to_c(const ParameterInfo& in, hapticd_parameter_info& out) noexcept {
  out = hapticd_parameter_info{};
  copy_text(out.name, in.name);
  switch (in.type) {
    case ParameterType::real:
      out.type = HAPTICD_PARAMETER_REAL;
      break;
    case ParameterType::integer:
      out.type = HAPTICD_PARAMETER_INTEGER;
      break;
    case ParameterType::boolean:
      out.type = HAPTICD_PARAMETER_BOOLEAN;
      break;
    case ParameterType::string:
      out.type = HAPTICD_PARAMETER_TEXT;
      break;
    case ParameterType::real_vector:
      out.type = HAPTICD_PARAMETER_REAL_VECTOR;
      break;
  }
  copy_text(out.unit, in.unit);
  copy_text(out.description, in.description);
  out.tunable = in.tunable ? 1 : 0;
  out.has_minimum = in.minimum ? 1 : 0;
  out.has_maximum = in.maximum ? 1 : 0;
  out.minimum_exclusive = in.minimum_exclusive ? 1 : 0;
  out.minimum = in.minimum.value_or(0.0);
  out.maximum = in.maximum.value_or(0.0);
  copy_text(out.value_text, in.value_text);
  out.value_count = static_cast<std::int32_t>(std::min<std::size_t>(in.value.size(), HAPTICD_MAX_VALUES));
  for (std::size_t i = 0; i < static_cast<std::size_t>(out.value_count); ++i) out.values[i] = in.value[i];
}

bool from_c(const hapticd_command& in, client::EngineCommand& out) noexcept {
  switch (in.kind) {
    case HAPTICD_COMMAND_WRENCH:
      out.kind = client::CommandKind::wrench;
      break;
    case HAPTICD_COMMAND_COUPLING:
      out.kind = client::CommandKind::coupling;
      break;
    case HAPTICD_COMMAND_MOTION:
      out.kind = client::CommandKind::motion;
      break;
    default:
      return false;
  }
  out.state_serial = in.state_serial;
  out.wrench = from_c(in.wrench);
  out.local_model.reset();
  if (in.has_local_model != 0) {
    client::LocalModel m;
    m.anchor = from_c(in.local_model.anchor);
    for (int i = 0; i < 6; ++i) {
      m.stiffness[i] = in.local_model.stiffness[i];
      m.damping[i] = in.local_model.damping[i];
    }
    out.local_model = m;
  }
  out.pose = from_c(in.pose);
  out.twist = from_c(in.twist);
  return true;
}

}  // namespace hapticd::client_c
