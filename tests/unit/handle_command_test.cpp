// A handle device's command (hapticd/handle.hpp, Device::write_handle): the axes' efforts the server's chain and
// safety layer work on, as the newtons and newton-metres the device takes - for every combination of actuated
// torque and gripper - and the defaults of the two writes, which refuse what a device does not take.
#include <gtest/gtest.h>

#include "hapticd/device.hpp"
#include "hapticd/handle.hpp"

namespace hapticd {
namespace {

JointVector efforts(std::initializer_list<double> values) {
  JointVector e(static_cast<int>(values.size()));
  int i = 0;
  for (double v : values) e[i++] = v;
  return e;
}

TEST(HandleCommand, TheAxesEffortsAreTheForceTheTorqueAndTheGripperForce) {
  HandleDescription h;  // 3 forces
  HandleCommand c = handle_command(h, efforts({1, 2, 3}));
  EXPECT_EQ(c.force_n, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(c.torque_nm, Eigen::Vector3d::Zero());
  EXPECT_EQ(c.gripper_force_n, 0.0);
  h.actuated_gripper = true;  // 3 forces and the gripper (an omega.7)
  c = handle_command(h, efforts({1, 2, 3, 4}));
  EXPECT_EQ(c.torque_nm, Eigen::Vector3d::Zero());
  EXPECT_EQ(c.gripper_force_n, 4.0);
  h.actuated_torque = true;  // 6 and the gripper (a sigma.7)
  c = handle_command(h, efforts({1, 2, 3, 0.1, 0.2, 0.3, 5}));
  EXPECT_EQ(c.force_n, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(c.torque_nm, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(c.gripper_force_n, 5.0);
  h.actuated_gripper = false;  // 6 (a Touch X with torques)
  c = handle_command(h, efforts({1, 2, 3, 0.1, 0.2, 0.3}));
  EXPECT_EQ(c.torque_nm, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(c.gripper_force_n, 0.0);
  // Fewer efforts than axes: the missing ones are zero, never read past the vector.
  c = handle_command(h, efforts({1, 2}));
  EXPECT_EQ(c.force_n, Eigen::Vector3d(1, 2, 0));
  EXPECT_EQ(c.torque_nm, Eigen::Vector3d::Zero());
}

// A device that implements neither write: each default refuses with a reason that says which to implement.
class Silent final : public Device {
 public:
  void configure(const Parameters&, const PluginContext&) override {}
  [[nodiscard]] const DeviceDescription& description() const override { return d_; }
  Outcome enable() override { return Outcome::success(); }
  Outcome read(const CycleTime&, DeviceState&) override { return Outcome::success(); }
  void disable() override {}

 private:
  DeviceDescription d_;
};

TEST(HandleCommand, EachWriteThatADeviceDoesNotImplementRefuses) {
  Silent s;
  const Outcome joints = s.write(CycleTime{}, JointCommand{});
  EXPECT_FALSE(joints.ok());
  EXPECT_NE(std::string(joints.reason).find("write_handle"), std::string::npos);
  const Outcome handle = s.write_handle(CycleTime{}, HandleCommand{});
  EXPECT_FALSE(handle.ok());
  EXPECT_NE(std::string(handle.reason).find("a joint device: write"), std::string::npos);
}

}  // namespace
}  // namespace hapticd
