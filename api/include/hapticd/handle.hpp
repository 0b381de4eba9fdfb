#pragma once
// Devices whose interface is the handle (docs/devices.md): a Force Dimension omega or sigma, a 3D Systems Touch, a
// Haply Inverse3. Their kinematics live in the vendor's SDK; they report the handle's pose, velocity, buttons and
// gripper and take a force (and a torque, and a gripper force). The server runs them with the chain it runs on
// joint devices by giving them axes: the handle's actuated directions, in the device's base frame,
//   x, y, z                 position [m], velocity [m/s], effort: force [N]          (always)
//   rx, ry, rz              rotation vector [rad], angular velocity [rad/s], torque [N m] (actuated_torque)
//   gripper                 opening [rad], its rate [rad/s], force [N]                (actuated_gripper)
// so that the joint-space parts of the chain (the command's limits, the safe mode's damping, the history and the
// recordings) apply to them unchanged, and a command's `torque_nm` is the handle's force, torque and gripper force
// on those axes. The device plugin fills only DeviceState::handle; the server fills the axes from it, and hands it
// its command in newtons and newton-metres (HandleCommand, Device::write_handle), never as joint torques.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hapticd/export.hpp"
#include "hapticd/joint_vector.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd {

struct JointDescription;

// Which interface a device offers; a chain plugin says which it can drive (PluginDescriptor::device_interfaces).
enum class DeviceInterface : std::uint8_t { joints = 1, handle = 2 };
using DeviceInterfaces = std::uint8_t;  // a set of DeviceInterface bits
inline constexpr DeviceInterfaces kJointsOnly = static_cast<DeviceInterfaces>(DeviceInterface::joints);
inline constexpr DeviceInterfaces kHandleOnly = static_cast<DeviceInterfaces>(DeviceInterface::handle);
inline constexpr DeviceInterfaces kEitherInterface = kJointsOnly | kHandleOnly;
[[nodiscard]] constexpr bool supports(DeviceInterfaces set, DeviceInterface i) noexcept {
  return (set & static_cast<DeviceInterfaces>(i)) != 0;
}
[[nodiscard]] HAPTICD_API const char* to_string(DeviceInterface i) noexcept;

// What a handle device offers, from its vendor's documentation and what the SDK reports of the unit.
struct HandleDescription {
  bool senses_orientation = false;  // the handle's orientation is measured (a 6-DOF sensed handle)
  bool actuated_torque = false;     // torques can be applied about the handle (6-DOF force feedback)
  bool has_gripper = false;         // a gripper's opening is measured
  bool actuated_gripper = false;    // and a force can be applied to it
  int buttons = 0;                  // buttons reported in HandleState::buttons (bit i: button i)
  // The reachable box of the handle point in the device's base frame [m].
  Eigen::Vector3d workspace_min = Eigen::Vector3d::Constant(-0.05);
  Eigen::Vector3d workspace_max = Eigen::Vector3d::Constant(0.05);
  double max_force_n = 0.0;          // the largest force the device may be commanded (per axis)
  double continuous_force_n = 0.0;   // sustainable force (0: max_force_n)
  double max_torque_nm = 0.0;        // actuated_torque
  double max_gripper_force_n = 0.0;  // actuated_gripper
  double max_speed_m_s = 1.0;        // the handle's speed the device is specified for
  double max_angular_speed_rad_s = 20.0;
  // The vendor's recommended largest stiffness and damping to render (a wall, a position loop's gains).
  double recommended_stiffness_n_per_m = 0.0;
  double recommended_damping_n_s_per_m = 0.0;
  double recommended_rotational_stiffness_nm_per_rad = 0.0;
  double recommended_rotational_damping_nm_s_per_rad = 0.0;

  // 3 or 6 (orientation sensed), the gripper counted apart.
  [[nodiscard]] int degrees_of_freedom() const noexcept { return senses_orientation ? 6 : 3; }
  // The actuated axes: 3 forces, 3 torques when actuated_torque, 1 gripper force when actuated_gripper.
  [[nodiscard]] int axes() const noexcept { return 3 + (actuated_torque ? 3 : 0) + (actuated_gripper ? 1 : 0); }
};

// One sample of the handle, in the device's base frame (the server turns pose and twist into the world).
struct HandleState {
  Pose pose;
  Twist twist;                // at the handle point
  std::uint32_t buttons = 0;  // bit i: button i pressed
  double gripper = 0.0;       // opening [rad] (has_gripper)
  double gripper_rate = 0.0;  // [rad/s]
  // The device's own linkage as its SDK reports it, for information (the session API; the server does not model
  // it): a Touch's three joint angles then its three gimbal angles [rad]. The first `linkage_count` are valid.
  std::array<double, 6> linkage{};
  int linkage_count = 0;
};

// The axes a handle device runs with, named and limited from its description (the server sets them as the
// device's joints; a plugin need not).
[[nodiscard]] HAPTICD_API std::vector<JointDescription> handle_axes(const HandleDescription& handle);
// What a handle device is asked to apply, held until the next command: in the device's base frame at the handle
// point (as HandleState), finite and within the description's limits (the server's safety layer has made it so).
struct HandleCommand {
  Eigen::Vector3d force_n = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_nm = Eigen::Vector3d::Zero();  // zero unless actuated_torque
  double gripper_force_n = 0.0;                         // zero unless actuated_gripper
};
// The handle command that the axes' efforts (x, y, z, then rx, ry, rz with actuated_torque, then the gripper with
// actuated_gripper; joint_vector of size axes()) stand for. Real-time safe; missing axes count as zero.
[[nodiscard]] HAPTICD_API HandleCommand handle_command(const HandleDescription& handle,
                                                       const JointVector& effort) noexcept;

// The axes' positions and velocities from the handle's state (real-time safe: `position` and `velocity` are
// resized within their fixed capacity).
HAPTICD_API void handle_to_axes(const HandleDescription& handle, const HandleState& state, JointVector& position,
                                JointVector& velocity) noexcept;

}  // namespace hapticd
