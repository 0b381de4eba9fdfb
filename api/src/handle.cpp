#include "hapticd/handle.hpp"

#include <Eigen/Geometry>

#include "hapticd/device_description.hpp"

namespace hapticd {

const char* to_string(DeviceInterface i) noexcept { return i == DeviceInterface::handle ? "handle" : "joints"; }

std::vector<JointDescription> handle_axes(const HandleDescription& h) {
  std::vector<JointDescription> axes;
  const double continuous = h.continuous_force_n > 0.0 ? h.continuous_force_n : h.max_force_n;
  const char* names[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    axes.push_back({names[i], h.workspace_min[i], h.workspace_max[i], h.max_speed_m_s, h.max_force_n, continuous});
  if (h.actuated_torque) {
    const char* rotation[] = {"rx", "ry", "rz"};
    for (const char* n : rotation) axes.push_back({n, -1e9, 1e9, h.max_angular_speed_rad_s, h.max_torque_nm, 0.0});
  }
  if (h.actuated_gripper) axes.push_back({"gripper", -1e9, 1e9, 1e9, h.max_gripper_force_n, 0.0});
  return axes;
}

HandleCommand handle_command(const HandleDescription& h, const JointVector& e) noexcept {
  HandleCommand c;
  const auto at = [&](int i) { return i < e.size() ? e[i] : 0.0; };
  c.force_n = Eigen::Vector3d(at(0), at(1), at(2));
  int next = 3;
  if (h.actuated_torque) {
    c.torque_nm = Eigen::Vector3d(at(3), at(4), at(5));
    next += 3;
  }
  if (h.actuated_gripper) c.gripper_force_n = at(next);
  return c;
}

void handle_to_axes(const HandleDescription& h, const HandleState& s, JointVector& position,
                    JointVector& velocity) noexcept {
  const int n = h.axes();
  position.resize(n);
  velocity.resize(n);
  position.head<3>() = s.pose.position;
  velocity.head<3>() = s.twist.linear;
  int next = 3;
  if (h.actuated_torque) {
    const Eigen::AngleAxisd r(s.pose.orientation.normalized());
    position.segment<3>(next) = r.angle() * r.axis();
    velocity.segment<3>(next) = s.twist.angular;
    next += 3;
  }
  if (h.actuated_gripper) {
    position[next] = s.gripper;
    velocity[next] = s.gripper_rate;
  }
}

}  // namespace hapticd
