#include "doors/ros2/ros2_messages.hpp"

#include <Eigen/Geometry>
#include <algorithm>

namespace hapticd::server::ros2 {
namespace {

char* text(const std::string& s) noexcept { return const_cast<char*>(s.c_str()); }  // written, never changed

void set(geometry_msgs_msg_dds__Point_& p, const Eigen::Vector3d& v) noexcept { p = {v.x(), v.y(), v.z()}; }
void set(geometry_msgs_msg_dds__Vector3_& p, const Eigen::Vector3d& v) noexcept { p = {v.x(), v.y(), v.z()}; }
void set(geometry_msgs_msg_dds__Quaternion_& q, const Eigen::Quaterniond& r) noexcept {
  q = {r.x(), r.y(), r.z(), r.w()};  // ROS's order: x, y, z, w
}
Pose pose_of(const hapticd_msg_Pose& p) {
  Pose out;
  out.position = Eigen::Vector3d(p.position[0], p.position[1], p.position[2]);
  out.orientation = Eigen::Quaterniond(p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3]);
  if (out.orientation.norm() > 0.0) out.orientation.normalize();
  return out;
}
void set(geometry_msgs_msg_dds__Transform_& t, const Pose& p) noexcept {
  set(t.translation, p.position);
  set(t.rotation, p.orientation);
}
template <class T>
void set_sequence(T& sequence, std::vector<typename std::remove_pointer_t<decltype(sequence._buffer)>>& v) noexcept {
  sequence._buffer = v.data();
  sequence._length = sequence._maximum = static_cast<std::uint32_t>(v.size());
  sequence._release = false;
}

}  // namespace

builtin_interfaces_msg_dds__Time_ ros_time(std::int64_t unix_ns) noexcept {
  const std::int64_t s = unix_ns >= 0 ? unix_ns / 1'000'000'000 : (unix_ns - 999'999'999) / 1'000'000'000;
  return {static_cast<std::int32_t>(s), static_cast<std::uint32_t>(unix_ns - s * 1'000'000'000)};
}

DeviceMessages::DeviceMessages(const std::string& device, const DeviceDescription& description,
                               const std::string& world_frame, const std::string& base_link)
    : world_frame_(world_frame),
      base_frame_(device + "/" + (base_link.empty() ? std::string("base") : base_link)),
      handle_frame_(device + "/handle"),
      base_(description.base_pose) {
  const bool handle_device = description.interface == DeviceInterface::handle;
  if (!handle_device) {
    for (const JointDescription& j : description.joints) joint_names_.push_back(j.name);
    for (const std::string& n : joint_names_) joint_name_pointers_.push_back(text(n));
    position_.resize(joint_names_.size());
    velocity_.resize(joint_names_.size());
    effort_.resize(joint_names_.size());
  } else {
    gripper_ = description.handle.has_gripper;
    axes_.resize(gripper_ ? 1 : 0);
    buttons_.resize(static_cast<std::size_t>(std::clamp(description.handle.buttons, 0, 32)));
  }
  pose_.header.frame_id = text(world_frame_);
  twist_.header.frame_id = text(handle_frame_);
  wrench_.header.frame_id = text(handle_frame_);
  joints_.header.frame_id = text(base_frame_);
  joy_.header.frame_id = text(handle_frame_);
  set_sequence(joints_.name, joint_name_pointers_);
  set_sequence(joints_.position, position_);
  set_sequence(joints_.velocity, velocity_);
  set_sequence(joints_.effort, effort_);
  set_sequence(joy_.axes, axes_);
  set_sequence(joy_.buttons, buttons_);
  transforms_[0].header.frame_id = text(world_frame_);
  transforms_[0].child_frame_id = text(base_frame_);
  transforms_[1].header.frame_id = text(base_frame_);
  transforms_[1].child_frame_id = text(handle_frame_);
  tf_.transforms._buffer = transforms_;
  tf_.transforms._length = tf_.transforms._maximum = 2;
  tf_.transforms._release = false;
}

void DeviceMessages::fill(const hapticd_msg_DeviceState& s, std::int64_t unix_ns) {
  const builtin_interfaces_msg_dds__Time_ stamp = ros_time(unix_ns);
  for (std_msgs_msg_dds__Header_* h : {&pose_.header, &twist_.header, &wrench_.header, &joints_.header, &joy_.header,
                                       &transforms_[0].header, &transforms_[1].header})
    h->stamp = stamp;
  const Pose handle = pose_of(s.handle_pose);
  set(pose_.pose.position, handle.position);
  set(pose_.pose.orientation, handle.orientation);
  // The twist and the wrench in the handle's axes (at its origin, where the state gives them).
  const Eigen::Matrix3d to_handle = handle.orientation.conjugate().toRotationMatrix();
  const auto in_handle = [&](const double* v) {
    return Eigen::Vector3d(to_handle * Eigen::Vector3d(v[0], v[1], v[2]));
  };
  set(twist_.twist.linear, in_handle(s.twist));
  set(twist_.twist.angular, in_handle(s.twist + 3));
  set(wrench_.wrench.force, in_handle(s.operator_wrench));
  set(wrench_.wrench.torque, in_handle(s.operator_wrench + 3));
  const std::size_t n = std::min<std::size_t>(position_.size(), static_cast<std::size_t>(std::clamp(s.dof, 0, 10)));
  for (std::size_t i = 0; i < n; ++i) {
    position_[i] = s.position[i];
    velocity_[i] = s.velocity[i];
    effort_[i] = s.torque[i];
  }
  if (gripper_) axes_[0] = static_cast<float>(s.gripper);
  for (std::size_t i = 0; i < buttons_.size(); ++i) buttons_[i] = (s.buttons >> i) & 1u;
  set(transforms_[0].transform, base_);
  Pose relative;
  relative.orientation = base_.orientation.conjugate() * handle.orientation;
  relative.position = base_.orientation.conjugate() * (handle.position - base_.position);
  set(transforms_[1].transform, relative);
}

}  // namespace hapticd::server::ros2
