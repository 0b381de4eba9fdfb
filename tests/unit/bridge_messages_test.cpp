// The gate's messages and events as pure functions of what the loop published (server/src/gate/
// messages): no DDS entity, no thread.
#include <gtest/gtest.h>

#include <memory>

#include "gate/messages.hpp"
#include "hapticd/dds/conversion.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

DeviceSnapshot running_snapshot() {
  DeviceSnapshot s;
  s.cycle = 41;
  s.time_ns = 20'500'000;
  s.handle_pose.position = Eigen::Vector3d(0.1, -0.2, 0.3);
  s.position = JointVector::Constant(3, 0.5);
  s.velocity = JointVector::Constant(3, -1.0);
  s.torque = JointVector::Constant(3, 2.0);
  s.engine_weight = 1.0;
  s.engine_sequence = 7;
  return s;
}

TEST(BridgeMessages, TheStateCarriesTheSnapshotItsLabelsAndItsFlags) {
  DeviceSnapshot s = running_snapshot();
  s.saturated = true;
  const StateLabels labels{"v3", 42, "admittance", "engine", hapticd_msg_LoopSummary{}};
  const hapticd_msg_DeviceState m = state_message(s, labels);
  EXPECT_EQ(dds::text_of(m.device), "v3");
  EXPECT_EQ(dds::text_of(m.scheme), "admittance");
  EXPECT_EQ(dds::text_of(m.owner), "engine");
  EXPECT_EQ(m.serial, 42u);
  EXPECT_EQ(m.cycle, 41u);
  EXPECT_EQ(m.dof, 3);
  EXPECT_DOUBLE_EQ(m.handle_pose.position[1], -0.2);
  EXPECT_DOUBLE_EQ(m.velocity[2], -1.0);
  EXPECT_DOUBLE_EQ(m.torque[0], 2.0);
  EXPECT_EQ(m.engine_serial, 7u);
  EXPECT_EQ(m.mode, hapticd_msg_MODE_RUNNING);
  EXPECT_EQ(m.flags, hapticd_msg_FLAG_TORQUE_SATURATED | hapticd_msg_FLAG_ENGINE_ACTIVE);
  EXPECT_EQ(dds::text_of(m.fault), "");

  s.fault = DeviceFault::emergency_stop;
  s.estop = true;
  s.engine_stale = true;
  const hapticd_msg_DeviceState safe = state_message(s, labels);
  EXPECT_EQ(safe.mode, hapticd_msg_MODE_SAFE);
  EXPECT_EQ(dds::text_of(safe.fault), "emergency_stop");
  EXPECT_EQ(safe.flags & (hapticd_msg_FLAG_ESTOP | hapticd_msg_FLAG_FAULT | hapticd_msg_FLAG_ENGINE_STALE),
            hapticd_msg_FLAG_ESTOP | hapticd_msg_FLAG_FAULT | hapticd_msg_FLAG_ENGINE_STALE);
  EXPECT_EQ(safe.flags & hapticd_msg_FLAG_ENGINE_ACTIVE, 0u);  // stale input is not active
  s.fault = DeviceFault::none;
  s.stopping = true;
  EXPECT_EQ(mode_of(s), hapticd_msg_MODE_STOPPING);
}

TEST(BridgeMessages, EventsFollowFromThePreviousAndTheCurrentView) {
  const std::vector<std::string> schemes{"admittance", "impedance"};
  PublishedView before;  // starting
  PublishedView running;
  running.mode = hapticd_msg_MODE_RUNNING;
  EXPECT_EQ(events_between(before, running, schemes),
            (std::vector<EventText>{{hapticd_msg_EVENT_MODE, "running", "mode: running"}}));
  EXPECT_TRUE(events_between(running, running, schemes).empty());  // nothing changed, nothing said

  PublishedView stopped = running;
  stopped.mode = hapticd_msg_MODE_SAFE;
  stopped.fault = DeviceFault::emergency_stop;
  stopped.faults = 1;
  auto e = events_between(running, stopped, schemes);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0].kind, hapticd_msg_EVENT_MODE);
  EXPECT_EQ(e[1].kind, hapticd_msg_EVENT_ESTOP);
  EXPECT_EQ(e[1].code, "emergency_stop");

  // A second stop while already safe: the fault is the same, the count went up - an event of its own.
  PublishedView again = stopped;
  again.faults = 2;
  e = events_between(stopped, again, schemes);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].kind, hapticd_msg_EVENT_ESTOP);

  PublishedView overrun = again;
  overrun.fault = DeviceFault::loop_overrun;
  overrun.faults = 3;
  e = events_between(again, overrun, schemes);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].kind, hapticd_msg_EVENT_FAULT);
  EXPECT_EQ(e[0].code, fault_code(DeviceFault::loop_overrun));

  PublishedView recovered = overrun;
  recovered.mode = hapticd_msg_MODE_RUNNING;
  recovered.fault = DeviceFault::none;
  e = events_between(overrun, recovered, schemes);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[1].kind, hapticd_msg_EVENT_RECOVERED);
  EXPECT_EQ(e[1].code, fault_code(DeviceFault::loop_overrun));  // what it recovered from

  PublishedView switched = recovered;
  switched.scheme = 1;
  e = events_between(recovered, switched, schemes);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0], (EventText{hapticd_msg_EVENT_SCHEME, "impedance", "switched to scheme impedance"}));
  PublishedView unknown = switched;
  unknown.scheme = 5;  // no such scheme: nothing to name
  EXPECT_TRUE(events_between(switched, unknown, schemes).empty());

  // The engine turning stale is said once; turning fresh again is not an event.
  PublishedView stale = switched;
  stale.stale = true;
  ASSERT_EQ(events_between(switched, stale, schemes).size(), 1u);
  EXPECT_EQ(events_between(switched, stale, schemes)[0].kind, hapticd_msg_EVENT_ENGINE_STALE);
  EXPECT_TRUE(events_between(stale, stale, schemes).empty());
  EXPECT_TRUE(events_between(stale, switched, schemes).empty());
}

TEST(BridgeMessages, AFaultReportKeepsItsCyclesUpToTheMessagesCapacity) {
  auto report = std::make_unique<FaultReport>();
  report->fault = DeviceFault::joint_velocity;
  report->serial = 3;
  report->cycle = 900;
  report->count = 50;
  for (std::uint32_t k = 0; k < report->count; ++k) {
    report->records[k].cycle = 850 + k;
    report->records[k].position = JointVector::Constant(3, 0.01 * k);
    report->records[k].velocity = JointVector::Zero(3);
    report->records[k].torque = JointVector::Zero(3);
    report->records[k].handle_velocity = Eigen::Vector3d(0.0, 0.0, -0.001 * k);
  }
  auto m = std::make_unique<hapticd_msg_FaultReport>();
  fill_fault_report(*m, "v3", 3, *report);
  EXPECT_EQ(dds::text_of(m->device), "v3");
  EXPECT_EQ(dds::text_of(m->fault), fault_code(DeviceFault::joint_velocity));
  EXPECT_EQ(m->serial, 3u);
  EXPECT_EQ(m->record_count, 50);
  EXPECT_EQ(m->records[49].cycle, 899u);
  EXPECT_DOUBLE_EQ(m->records[10].position[2], 0.1);
  EXPECT_DOUBLE_EQ(m->records[20].handle_velocity[2], -0.02);
}

TEST(BridgeMessages, TheDescriptionSaysWhatTheDeviceDescribes) {
  Session s = test::build_test_session("server: {clock: lockstep}\ndevices:\n" + test::mass_spring_device_yaml("axis") +
                                       "    base_pose: {xyz: [0.5, -0.25, 0.125], rpy: [0, 0, 3.141592653589793]}\n");
  const hapticd_msg_DeviceDescription m = description_message(test::device_of(s).requests(), 2000.0, std::nullopt);
  EXPECT_STREQ(m.base_frame, "world");
  EXPECT_DOUBLE_EQ(m.base_pose.position[0], 0.5);
  EXPECT_DOUBLE_EQ(m.base_pose.position[1], -0.25);
  EXPECT_DOUBLE_EQ(m.base_pose.position[2], 0.125);
  EXPECT_NEAR(std::abs(m.base_pose.orientation[3]), 1.0, 1e-12);  // half a turn about z: [0, 0, 0, +-1]
  EXPECT_DOUBLE_EQ(m.workspace_min[0], m.workspace_max[0]);       // no safety box
  EXPECT_STREQ(m.device, "axis");
  EXPECT_STREQ(m.device_plugin, "test_mass_spring");
  EXPECT_TRUE(m.simulated);  // from DeviceDescription::simulated, not from the plugin's name
  EXPECT_EQ(m.dof, 1);
  EXPECT_DOUBLE_EQ(m.rate_hz, 2000.0);
}

}  // namespace
}  // namespace hapticd::server
