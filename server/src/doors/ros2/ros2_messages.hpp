#pragma once
// One device's state as ROS 2's messages (docs/ros2.md, "Topics, frames and units"): pure translation, unit-tested
// without DDS. Units are SI (REP 103). Frames: the world (ros2.world_frame) is hapticd's world frame; the device's
// base is "<device>/<its robot model's root link>" (a handle device: "<device>/base"), placed by the session's
// base_pose, so robot_state_publisher with frame_prefix "<device>/" hangs the arm's links under it; the handle is
// "<device>/handle". The pose is the handle's in the world; the twist and the operator's wrench are the handle's,
// expressed in the handle frame (at its origin, along its axes: a ROS frame says both). Stamps: the wall clock
// when the state is published.
#include <cstdint>
#include <string>
#include <vector>

#include "hapticd/device_description.hpp"
#include "hapticd_msg.h"
#include "ros2_msg.h"

namespace hapticd::server::ros2 {

// builtin_interfaces/Time of nanoseconds since the Unix epoch.
[[nodiscard]] builtin_interfaces_msg_dds__Time_ ros_time(std::int64_t unix_ns) noexcept;

class DeviceMessages {
 public:
  // base_link: the robot model's root link ("" for a handle device: "base").
  DeviceMessages(const std::string& device, const DeviceDescription& description, const std::string& world_frame,
                 const std::string& base_link);
  DeviceMessages(const DeviceMessages&) = delete;
  DeviceMessages& operator=(const DeviceMessages&) = delete;

  // Every message of `state`, stamped `unix_ns`. The strings and sequences point into this object.
  void fill(const hapticd_msg_DeviceState& state, std::int64_t unix_ns);

  [[nodiscard]] const geometry_msgs_msg_dds__PoseStamped_& pose() const noexcept { return pose_; }
  [[nodiscard]] const geometry_msgs_msg_dds__TwistStamped_& twist() const noexcept { return twist_; }
  [[nodiscard]] const geometry_msgs_msg_dds__WrenchStamped_& wrench() const noexcept { return wrench_; }
  [[nodiscard]] const sensor_msgs_msg_dds__JointState_& joint_state() const noexcept { return joints_; }
  [[nodiscard]] const sensor_msgs_msg_dds__Joy_& joy() const noexcept { return joy_; }
  // world -> base -> handle.
  [[nodiscard]] const tf2_msgs_msg_dds__TFMessage_& tf() const noexcept { return tf_; }
  [[nodiscard]] const std::string& base_frame() const noexcept { return base_frame_; }
  [[nodiscard]] const std::string& handle_frame() const noexcept { return handle_frame_; }

 private:
  std::string world_frame_, base_frame_, handle_frame_;
  Pose base_;  // the device's base in the world
  std::vector<std::string> joint_names_;
  std::vector<char*> joint_name_pointers_;
  std::vector<double> position_, velocity_, effort_;
  std::vector<float> axes_;
  std::vector<std::int32_t> buttons_;
  bool gripper_ = false;
  geometry_msgs_msg_dds__PoseStamped_ pose_{};
  geometry_msgs_msg_dds__TwistStamped_ twist_{};
  geometry_msgs_msg_dds__WrenchStamped_ wrench_{};
  sensor_msgs_msg_dds__JointState_ joints_{};
  sensor_msgs_msg_dds__Joy_ joy_{};
  geometry_msgs_msg_dds__TransformStamped_ transforms_[2]{};
  tf2_msgs_msg_dds__TFMessage_ tf_{};
};

}  // namespace hapticd::server::ros2
