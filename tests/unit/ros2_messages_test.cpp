// A device's state as ROS 2's messages (server/src/doors/ros2/ros2_messages.hpp, docs/ros2.md): stamps, frames,
// units and the order of ROS's fields, checked value by value.
#include "doors/ros2/ros2_messages.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

namespace hapticd::server::ros2 {
namespace {

Eigen::Vector3d vec(const geometry_msgs_msg_dds__Vector3_& v) { return {v.x, v.y, v.z}; }
Eigen::Quaterniond quat(const geometry_msgs_msg_dds__Quaternion_& q) { return {q.w, q.x, q.y, q.z}; }

DeviceDescription joint_device() {
  DeviceDescription d;
  d.interface = DeviceInterface::joints;
  for (const char* n : {"joint1", "joint2", "joint3"}) d.joints.push_back(JointDescription{n});
  d.base_pose.position = {0.1, -0.2, 0.3};
  d.base_pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  return d;
}

hapticd_msg_DeviceState state(const Eigen::Quaterniond& q) {
  hapticd_msg_DeviceState s{};
  s.handle_pose.position[0] = 0.4;
  s.handle_pose.position[1] = 0.5;
  s.handle_pose.position[2] = -0.1;
  s.handle_pose.orientation[0] = q.w();  // hapticd's order: w, x, y, z
  s.handle_pose.orientation[1] = q.x();
  s.handle_pose.orientation[2] = q.y();
  s.handle_pose.orientation[3] = q.z();
  const double twist[6] = {0.1, 0.2, 0.3, 1.0, 2.0, 3.0}, wrench[6] = {5.0, -4.0, 3.0, 0.5, 0.25, -0.125};
  std::copy(twist, twist + 6, s.twist);
  std::copy(wrench, wrench + 6, s.operator_wrench);
  s.dof = 3;
  for (int i = 0; i < 3; ++i) {
    s.position[i] = 0.1 * (i + 1);
    s.velocity[i] = -0.2 * (i + 1);
    s.torque[i] = 1.5 * (i + 1);
  }
  s.buttons = 0b101;
  s.gripper = 0.25;
  return s;
}

TEST(Ros2Messages, StampsAreSecondsAndNanosecondsOfTheUnixEpoch) {
  const auto t = ros_time(1'765'000'000'123'456'789);
  EXPECT_EQ(t.sec, 1'765'000'000);
  EXPECT_EQ(t.nanosec, 123'456'789u);
  const auto before = ros_time(-1);  // nanosec stays in [0, 1e9)
  EXPECT_EQ(before.sec, -1);
  EXPECT_EQ(before.nanosec, 999'999'999u);
}

TEST(Ros2Messages, PoseInTheWorldTwistAndWrenchInTheHandleFrameJointsAndTf) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  DeviceMessages m("vishard3", joint_device(), "world", "base");
  m.fill(state(q), 1'765'000'000'500'000'000);

  const auto& pose = m.pose();
  EXPECT_STREQ(pose.header.frame_id, "world");
  EXPECT_EQ(pose.header.stamp.sec, 1'765'000'000);
  EXPECT_EQ(pose.header.stamp.nanosec, 500'000'000u);
  EXPECT_DOUBLE_EQ(pose.pose.position.x, 0.4);
  EXPECT_DOUBLE_EQ(pose.pose.position.z, -0.1);
  // ROS's quaternion is x, y, z, w.
  EXPECT_DOUBLE_EQ(pose.pose.orientation.x, q.x());
  EXPECT_DOUBLE_EQ(pose.pose.orientation.w, q.w());

  // The twist and the wrench: the world-frame vectors turned into the handle's axes.
  const Eigen::Matrix3d r = q.toRotationMatrix();
  EXPECT_STREQ(m.twist().header.frame_id, "vishard3/handle");
  EXPECT_STREQ(m.wrench().header.frame_id, "vishard3/handle");
  EXPECT_TRUE((r * vec(m.twist().twist.linear)).isApprox(Eigen::Vector3d(0.1, 0.2, 0.3), 1e-12));
  EXPECT_TRUE((r * vec(m.twist().twist.angular)).isApprox(Eigen::Vector3d(1, 2, 3), 1e-12));
  EXPECT_TRUE((r * vec(m.wrench().wrench.force)).isApprox(Eigen::Vector3d(5, -4, 3), 1e-12));
  EXPECT_TRUE((r * vec(m.wrench().wrench.torque)).isApprox(Eigen::Vector3d(0.5, 0.25, -0.125), 1e-12));

  const auto& j = m.joint_state();
  EXPECT_STREQ(j.header.frame_id, "vishard3/base");
  ASSERT_EQ(j.name._length, 3u);
  EXPECT_STREQ(j.name._buffer[2], "joint3");
  ASSERT_EQ(j.position._length, 3u);
  EXPECT_DOUBLE_EQ(j.position._buffer[1], 0.2);
  EXPECT_DOUBLE_EQ(j.velocity._buffer[2], -0.6);
  EXPECT_DOUBLE_EQ(j.effort._buffer[0], 1.5);

  // world -> vishard3/base -> vishard3/handle composes to the handle's pose.
  const auto& tf = m.tf();
  ASSERT_EQ(tf.transforms._length, 2u);
  const auto& a = tf.transforms._buffer[0];
  const auto& b = tf.transforms._buffer[1];
  EXPECT_STREQ(a.header.frame_id, "world");
  EXPECT_STREQ(a.child_frame_id, "vishard3/base");
  EXPECT_STREQ(b.header.frame_id, "vishard3/base");
  EXPECT_STREQ(b.child_frame_id, "vishard3/handle");
  const Eigen::Isometry3d base = Eigen::Translation3d(vec(a.transform.translation)) * quat(a.transform.rotation);
  const Eigen::Isometry3d rel = Eigen::Translation3d(vec(b.transform.translation)) * quat(b.transform.rotation);
  const Eigen::Isometry3d handle = base * rel;
  EXPECT_TRUE(handle.translation().isApprox(Eigen::Vector3d(0.4, 0.5, -0.1), 1e-12));
  EXPECT_TRUE(Eigen::Quaterniond(handle.rotation()).isApprox(q, 1e-12));
  EXPECT_NEAR(vec(a.transform.translation).y(), -0.2, 1e-15);
}

TEST(Ros2Messages, AHandleDeviceHasButtonsAndItsGripperAsAJoyAndABaseFrameOfItsOwn) {
  DeviceDescription d;
  d.interface = DeviceInterface::handle;
  d.handle.has_gripper = true;
  d.handle.buttons = 4;
  DeviceMessages m("falcon", d, "lab/world", "");
  m.fill(state(Eigen::Quaterniond::Identity()), 0);
  EXPECT_EQ(m.base_frame(), "falcon/base");
  EXPECT_EQ(m.joint_state().name._length, 0u);
  const auto& joy = m.joy();
  ASSERT_EQ(joy.buttons._length, 4u);
  EXPECT_EQ(joy.buttons._buffer[0], 1);
  EXPECT_EQ(joy.buttons._buffer[1], 0);
  EXPECT_EQ(joy.buttons._buffer[2], 1);
  EXPECT_EQ(joy.buttons._buffer[3], 0);
  ASSERT_EQ(joy.axes._length, 1u);
  EXPECT_FLOAT_EQ(joy.axes._buffer[0], 0.25f);
  EXPECT_STREQ(m.tf().transforms._buffer[0].header.frame_id, "lab/world");
}

}  // namespace
}  // namespace hapticd::server::ros2
