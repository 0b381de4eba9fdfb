// The client library's conversions between the wire types and its values (clients/lib/src/wire.*): every field
// arrives where the value type says, counts from the wire are bounded, names are bounded texts, and a state
// converts without touching the heap (it is converted on Cyclone's receive thread for every sample).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "../../clients/lib/src/wire.hpp"
#include "hapticd/dds/conversion.hpp"
#include "hapticd/testing/allocation_guard.hpp"

namespace hapticd::client {
namespace {

hapticd_msg_DeviceState wire_state() {
  hapticd_msg_DeviceState s{};
  dds::set_text(s.device, "vishard3");
  s.serial = 42;
  s.cycle = 7;
  s.loop_time_ns = 1'500'000'000;
  s.handle_pose.position[0] = 0.1;
  s.handle_pose.position[2] = -0.3;
  s.handle_pose.orientation[0] = std::sqrt(0.5);
  s.handle_pose.orientation[3] = std::sqrt(0.5);
  for (int i = 0; i < 6; ++i) {
    s.twist[i] = 1.0 + i;
    s.operator_wrench[i] = 10.0 + i;
    s.environment_wrench[i] = 20.0 + i;
  }
  s.target_pose.orientation[0] = 1.0;
  s.dof = 3;
  for (int i = 0; i < 10; ++i) {
    s.position[i] = 0.1 * i;
    s.velocity[i] = -0.1 * i;
    s.torque[i] = 2.0 * i;
  }
  s.mode = hapticd_msg_MODE_SAFE;
  s.flags = hapticd_msg_FLAG_ESTOP | hapticd_msg_FLAG_FAULT;
  dds::set_text(s.fault, "emergency_stop");
  dds::set_text(s.scheme, "resolved-acceleration-rac");  // longer than a short-string buffer
  dds::set_text(s.owner, "scene");
  s.engine_serial = 41;
  s.loop.rate_hz = 2000.0;
  s.loop.overruns = 3;
  return s;
}

TEST(ClientWire, AStateArrivesFieldByField) {
  DeviceState v;
  wire::from_msg(wire_state(), v);
  EXPECT_EQ(v.device, "vishard3");
  EXPECT_EQ(v.serial, 42u);
  EXPECT_EQ(v.cycle, 7u);
  EXPECT_DOUBLE_EQ(v.time_s(), 1.5);
  EXPECT_EQ(v.pose.position, Eigen::Vector3d(0.1, 0.0, -0.3));
  EXPECT_DOUBLE_EQ(v.pose.orientation.w(), std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(v.pose.orientation.z(), std::sqrt(0.5));
  EXPECT_EQ(v.twist.linear, Eigen::Vector3d(1.0, 2.0, 3.0));
  EXPECT_EQ(v.twist.angular, Eigen::Vector3d(4.0, 5.0, 6.0));
  EXPECT_EQ(v.operator_wrench.force, Eigen::Vector3d(10.0, 11.0, 12.0));
  EXPECT_EQ(v.operator_wrench.torque, Eigen::Vector3d(13.0, 14.0, 15.0));
  EXPECT_EQ(v.environment_wrench.torque, Eigen::Vector3d(23.0, 24.0, 25.0));
  ASSERT_EQ(v.dof, 3);
  ASSERT_EQ(v.position.size(), 3);  // the joints of the device, not the wire's ten
  EXPECT_DOUBLE_EQ(v.position[2], 0.2);
  EXPECT_DOUBLE_EQ(v.velocity[2], -0.2);
  EXPECT_DOUBLE_EQ(v.torque[2], 4.0);
  EXPECT_EQ(v.mode, Mode::safe);
  EXPECT_EQ(flag_names(v.flags), (std::vector<std::string>{"estop", "fault"}));
  EXPECT_EQ(v.fault, "emergency_stop");
  EXPECT_EQ(v.scheme, "resolved-acceleration-rac");
  EXPECT_EQ(v.owner, "scene");
  EXPECT_EQ(v.engine_serial, 41u);
  EXPECT_EQ(v.loop.overruns, 3u);
}

TEST(ClientWire, CountsAndEnumsFromTheWireAreBounded) {
  hapticd_msg_DeviceState s = wire_state();
  s.dof = 1000;
  s.mode = static_cast<hapticd_msg_DeviceMode>(77);
  std::memset(s.device, 'x', sizeof s.device);  // no terminating NUL
  DeviceState v;
  wire::from_msg(s, v);
  EXPECT_EQ(v.dof, kMaxJoints);
  EXPECT_EQ(v.mode, Mode::off);
  EXPECT_EQ(v.device.view().size(), 31u);  // a Name holds 31 characters

  hapticd_msg_Event e{};
  e.kind = static_cast<hapticd_msg_EventKind>(-3);
  dds::set_text(e.code, "stale");
  EXPECT_EQ(wire::from_msg(e).kind, EventKind::mode);
  EXPECT_EQ(wire::from_msg(e).code, "stale");

  auto report = std::make_unique<hapticd_msg_FaultReport>();
  report->dof = 3;
  report->record_count = 500;
  EXPECT_EQ(wire::from_msg(*report).records.size(), static_cast<std::size_t>(hapticd_msg_MAX_HISTORY));
  report->record_count = -1;
  EXPECT_TRUE(wire::from_msg(*report).records.empty());
}

TEST(ClientWire, ADescriptionWithoutAStartPoseHasNone) {
  auto d = std::make_unique<hapticd_msg_DeviceDescription>();
  dds::set_text(d->device, "v3");
  d->dof = 2;
  dds::set_text(d->joint_names[0].text, "q1");
  dds::set_text(d->joint_names[1].text, "q2");
  d->torque_peak[1] = 5.0;
  d->scheme_count = 2;
  dds::set_text(d->schemes[0].text, "default");
  dds::set_text(d->schemes[1].text, "impedance");
  dds::set_text(d->scheme_virtual_model[0].text, "admittance");
  d->base_pose.orientation[0] = 1.0;
  DeviceInfo info = wire::from_msg(*d);
  EXPECT_EQ(info.joint_names, (std::vector<std::string>{"q1", "q2"}));
  EXPECT_EQ(info.torque_peak.size(), 2);
  EXPECT_DOUBLE_EQ(info.torque_peak[1], 5.0);
  ASSERT_EQ(info.schemes.size(), 2u);
  EXPECT_EQ(info.schemes[0].virtual_model, "admittance");
  EXPECT_EQ(info.schemes[1].name, "impedance");
  EXPECT_FALSE(info.start_pose.has_value());  // all zeros: not started
  d->start_pose.orientation[0] = 1.0;
  EXPECT_TRUE(wire::from_msg(*d).start_pose.has_value());
}

TEST(ClientWire, AnEngineCommandLeavesAsTheWireSaysAndWithAValidAnchor) {
  Pose proxy;
  proxy.position = Eigen::Vector3d(0.1, 0.2, 0.3);
  Twist twist;
  twist.linear = Eigen::Vector3d(1.0, 0.0, 0.0);
  hapticd_msg_EngineCommand c;
  wire::to_msg(EngineCommand::coupling(proxy, twist, 9), "v3", c);
  EXPECT_EQ(c.kind, hapticd_msg_COMMAND_COUPLING);
  EXPECT_EQ(dds::text_of(c.device), "v3");
  EXPECT_EQ(c.state_serial, 9u);
  EXPECT_EQ(c.command_pose.position[1], 0.2);
  EXPECT_EQ(c.command_pose.orientation[0], 1.0);
  EXPECT_EQ(c.twist[0], 1.0);
  EXPECT_FALSE(c.local_model);
  EXPECT_EQ(c.anchor.orientation[0], 1.0);  // a valid quaternion even when unused

  EngineCommand w = EngineCommand::force(Wrench{Eigen::Vector3d(0.0, 0.0, -2.0), Eigen::Vector3d::Zero()}, 3);
  w.local_model = LocalModel{};
  w.local_model->stiffness[2] = 1000.0;
  wire::to_msg(w, "v3", c);
  EXPECT_EQ(c.kind, hapticd_msg_COMMAND_WRENCH);
  EXPECT_EQ(c.wrench[2], -2.0);
  EXPECT_TRUE(c.local_model);
  EXPECT_EQ(c.stiffness[2], 1000.0);
  EXPECT_EQ(wire::to_msg(RequestKind::group_recover), hapticd_msg_REQUEST_GROUP_RECOVER);
}

TEST(ClientWire, AStateAndAGroupStateConvertWithoutAllocating) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "a sanitizer owns malloc";
  const hapticd_msg_DeviceState s = wire_state();
  auto g = std::make_unique<hapticd_msg_GroupState>();
  g->device_count = 2;
  g->states[0] = s;
  g->states[1] = s;
  DeviceState v;
  auto group = std::make_unique<GroupState>();
  EXPECT_EQ(testing::count_allocations([&] {
              wire::from_msg(s, v);
              wire::from_msg(*g, *group);
            }),
            0u);
  EXPECT_EQ(group->device_count, 2);
  EXPECT_EQ(group->states[1].scheme, "resolved-acceleration-rac");
}

}  // namespace
}  // namespace hapticd::client
