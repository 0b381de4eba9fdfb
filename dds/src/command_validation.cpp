#include "hapticd/dds/command_validation.hpp"

#include <cmath>
#include <cstring>

#include "hapticd/dds/conversion.hpp"

namespace hapticd::dds {
namespace {

template <std::size_t N>
bool all_finite(const double (&v)[N]) noexcept {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}
bool all_finite(const hapticd_msg_Pose& p) noexcept { return all_finite(p.position) && all_finite(p.orientation); }

double norm3(const double* v) noexcept { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

double distance_from(const double* v, const std::array<double, 3>& origin) noexcept {
  const double d[3] = {v[0] - origin[0], v[1] - origin[1], v[2] - origin[2]};
  return norm3(d);
}

bool unit_quaternion(const hapticd_msg_Pose& p) noexcept {
  const double* q = p.orientation;
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return n > 0.9 && n < 1.1;  // normalised on use; anything further off is a mistake, not rounding
}

bool within(const double (&v)[6], double linear, double angular) noexcept {
  return norm3(v) <= linear && norm3(v + 3) <= angular;
}
bool non_negative_within(const double (&v)[6], double linear, double angular) noexcept {
  for (int i = 0; i < 6; ++i)
    if (v[i] < 0.0 || v[i] > (i < 3 ? linear : angular)) return false;
  return true;
}

}  // namespace

std::string_view to_string(RejectReason reason) noexcept {
  switch (reason) {
    case RejectReason::malformed:
      return "malformed";
    case RejectReason::non_finite:
      return "non-finite";
    case RejectReason::out_of_bounds:
      return "out of bounds";
    case RejectReason::out_of_order:
      return "out of order";
    case RejectReason::stale:
      return "stale";
    case RejectReason::not_owner:
      return "not the owner";
    case RejectReason::wrong_kind:
      return "wrong kind for the scheme";
    case RejectReason::other:
      return "other";
  }
  return "other";
}

ContentCheck check_command_content(const hapticd_msg_EngineCommand& c, const CommandBounds& b) noexcept {
  const auto reject = [](RejectReason r) { return ContentCheck{false, r}; };
  if (!valid_text(c.device) || !valid_text(c.engine) || text_of(c.device).empty() || text_of(c.engine).empty())
    return reject(RejectReason::malformed);
  // The enum and the bool are read as the bytes they are: a sample from anywhere may hold any value there.
  std::int32_t kind = 0;
  static_assert(sizeof kind == sizeof c.kind);
  std::memcpy(&kind, &c.kind, sizeof kind);
  if (kind != hapticd_msg_COMMAND_WRENCH && kind != hapticd_msg_COMMAND_COUPLING && kind != hapticd_msg_COMMAND_MOTION)
    return reject(RejectReason::malformed);
  unsigned char local_model = 0;
  std::memcpy(&local_model, &c.local_model, 1);
  if (local_model > 1) return reject(RejectReason::malformed);
  if (c.serial == 0) return reject(RejectReason::malformed);  // serial numbers start at 1
  if (!all_finite(c.wrench) || !all_finite(c.anchor) || !all_finite(c.stiffness) || !all_finite(c.damping) ||
      !all_finite(c.command_pose) || !all_finite(c.twist))
    return reject(RejectReason::non_finite);
  switch (kind) {
    case hapticd_msg_COMMAND_WRENCH:
      if (!within(c.wrench, b.max_force_n, b.max_torque_nm)) return reject(RejectReason::out_of_bounds);
      if (local_model != 0) {
        if (!unit_quaternion(c.anchor)) return reject(RejectReason::malformed);
        if (distance_from(c.anchor.position, b.base_position) > b.max_distance_m)
          return reject(RejectReason::out_of_bounds);
        if (!non_negative_within(c.stiffness, b.max_stiffness_n_per_m, b.max_rotational_stiffness_n_m_per_rad) ||
            !non_negative_within(c.damping, b.max_damping_n_s_per_m, b.max_rotational_damping_n_m_s))
          return reject(RejectReason::out_of_bounds);
      }
      break;
    case hapticd_msg_COMMAND_COUPLING:
    case hapticd_msg_COMMAND_MOTION:
      if (!unit_quaternion(c.command_pose)) return reject(RejectReason::malformed);
      if (distance_from(c.command_pose.position, b.base_position) > b.max_distance_m)
        return reject(RejectReason::out_of_bounds);
      if (!within(c.twist, b.max_speed_m_s, b.max_angular_speed_rad_s)) return reject(RejectReason::out_of_bounds);
      break;
    default:
      return reject(RejectReason::malformed);
  }
  return ContentCheck{true, RejectReason::other};
}

EngineInput to_engine_input(const hapticd_msg_EngineCommand& c) noexcept {
  EngineInput e;
  e.sequence = c.serial;
  const auto twist = [](const double(&v)[6]) {
    Twist t;
    t.linear = Eigen::Vector3d(v[0], v[1], v[2]);
    t.angular = Eigen::Vector3d(v[3], v[4], v[5]);
    return t;
  };
  switch (c.kind) {
    case hapticd_msg_COMMAND_WRENCH:
      e.has_wrench = true;
      e.wrench.force = Eigen::Vector3d(c.wrench[0], c.wrench[1], c.wrench[2]);
      e.wrench.torque = Eigen::Vector3d(c.wrench[3], c.wrench[4], c.wrench[5]);
      if (c.local_model) {
        e.has_local_model = true;
        e.anchor = to_pose(c.anchor);
        e.anchor.orientation.normalize();
        e.stiffness = to_vector6(c.stiffness);
        e.damping = to_vector6(c.damping);
      }
      break;
    case hapticd_msg_COMMAND_COUPLING:
      e.has_proxy = true;
      e.proxy_pose = to_pose(c.command_pose);
      e.proxy_pose.orientation.normalize();
      e.proxy_twist = twist(c.twist);
      break;
    case hapticd_msg_COMMAND_MOTION:
      e.has_motion = true;
      e.motion_pose = to_pose(c.command_pose);
      e.motion_pose.orientation.normalize();
      e.motion_twist = twist(c.twist);
      break;
    default:
      break;
  }
  return e;
}

}  // namespace hapticd::dds
