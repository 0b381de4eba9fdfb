// The device lifecycle through the session (plugin API 8): enable, homing where the device needs it, a fault
// reset when a recovery is carried out, and the device's reason in its fault. A step that fails holds only its
// own device in the safe state.
#include <gtest/gtest.h>

#include "hapticd/server/session.hpp"
#include "session/device_session.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

Session two_devices(const std::string& first_parameters, const std::string& first_controller_parameters = "") {
  return test::build_test_session("server: {clock: lockstep, seed: 3}\ndevices:\n" +
                                  test::mass_spring_device_yaml("a", first_parameters, first_controller_parameters) +
                                  test::mass_spring_device_yaml("b"));
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(DeviceLifecycle, ADeviceThatNeedsHomingIsHomedBeforeItsFirstRead) {
  Session s = two_devices(", homing: true");
  s.step(100);
  EXPECT_EQ(s.device("a").fault, "");  // read() fails until home(): the server homed it
  EXPECT_EQ(s.device("b").fault, "");
}

TEST(DeviceLifecycle, AFailedEnableOrHomingHoldsOnlyThatDeviceWithTheReason) {
  for (const std::string& injected :
       {std::string(", fail_enable: true"), std::string(", homing: true, fail_homing: true")}) {
    Session s = two_devices(injected);
    s.step(100);
    const std::string fault = s.device("a").fault;
    EXPECT_TRUE(contains(fault, "injected")) << fault;
    EXPECT_TRUE(
        contains(fault, injected.find("homing") != std::string::npos ? "homing failed" : "could not be enabled"))
        << fault;
    EXPECT_EQ(s.device("a").command.torque_nm[0], 0.0);
    EXPECT_EQ(s.device("b").fault, "");
    EXPECT_GT(std::abs(s.device("b").command.torque_nm[0]), 0.0);  // the other device runs
    const RuntimeReply recover = s.request("a", {DeviceRequest::Kind::recover, "", {}});
    EXPECT_FALSE(recover.accepted);
    EXPECT_TRUE(contains(recover.message, "never ran")) << recover.message;
  }
}

TEST(DeviceLifecycle, AReadFaultShowsTheDevicesReasonAndARecoveryResetsIt) {
  Session s = two_devices(", fail_read_at_cycle: 50");
  s.step(400);
  const DeviceView faulted = s.device("a");
  EXPECT_TRUE(contains(faulted.fault, "device read failed: injected read failure")) << faulted.fault;
  ASSERT_TRUE(faulted.at_rest);
  ASSERT_TRUE(s.request("a", {DeviceRequest::Kind::recover, "", {}}).accepted);
  s.step(400);
  // The latched read fault was reset (else the next read would have faulted again) and the chain runs.
  const DeviceView recovered = s.device("a");
  EXPECT_EQ(recovered.fault, "");
  EXPECT_EQ(recovered.recoveries, 1u);
  EXPECT_EQ(recovered.faults, 1u);
  EXPECT_GT(std::abs(recovered.command.torque_nm[0]), 0.0);
}

TEST(DeviceLifecycle, ARefusedFaultResetKeepsTheDeviceSafeAndSaysWhy) {
  Session s = two_devices(", fail_read_at_cycle: 50, refuse_fault_reset: true");
  s.step(400);
  ASSERT_TRUE(s.request("a", {DeviceRequest::Kind::recover, "", {}}).accepted);
  s.step(100);
  const DeviceView v = s.device("a");
  EXPECT_TRUE(contains(v.fault, "device read failed: injected fault-reset failure")) << v.fault;
  EXPECT_EQ(v.recoveries, 0u);
  EXPECT_EQ(s.impl().devices[0]->status().refused_recoveries(), 1u);
  EXPECT_EQ(v.command.torque_nm[0], 0.0);
  EXPECT_EQ(s.device("b").fault, "");
}

TEST(DeviceLifecycle, AFailedDisableIsReportedAfterEveryDeviceIsDisabled) {
  Session s = two_devices(", throw_in_disable: true");
  s.step(10);
  try {
    s.stop();
    ADD_FAILURE() << "stop() did not report the failed disable";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), "a: disable() threw: injected disable failure")) << e.what();
  }
  EXPECT_EQ(s.impl().devices[1]->disable_error(), "");  // the other device was disabled too
}

TEST(DeviceLifecycle, APluginThatThrowsAsItIsDeactivatedDoesNotKeepItsDeviceFromBeingDisabled) {
  // The controller's deactivate() throws at the end: the device's disable() still runs (it throws too here,
  // which is how the test sees it ran), the other device is disabled, and stop() names both failures.
  Session s = two_devices(", throw_in_disable: true", ", throw_in_deactivate: true");
  s.step(10);
  try {
    s.stop();
    ADD_FAILURE() << "stop() did not report the failures";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), "a: disable() threw: injected disable failure")) << e.what();
    EXPECT_TRUE(contains(e.what(), "device 'a': scheme 'default', controller 'test_pd': injected deactivate failure"))
        << e.what();
  }
  EXPECT_EQ(s.impl().devices[1]->disable_error(), "");
}

TEST(DeviceLifecycle, APluginThatThrowsAsAFaultTakesItsSchemeOutIsReportedAndTheRunGoesOn) {
  // A read fault at cycle 50 takes device a's chain out of the loop; the monitor's service() deactivates it
  // and the controller throws. The step does not: the fault stands with its own reason, device b runs on,
  // and stop() reports what the plugin threw.
  Session s = two_devices(", fail_read_at_cycle: 50", ", throw_in_deactivate: true");
  EXPECT_NO_THROW(s.step(400));
  EXPECT_TRUE(contains(s.device("a").fault, "injected read failure")) << s.device("a").fault;
  EXPECT_EQ(s.device("b").fault, "");
  EXPECT_GT(std::abs(s.device("b").command.torque_nm[0]), 0.0);
  try {
    s.stop();
    ADD_FAILURE() << "stop() did not report the plugin's failure";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), "plugins failed as they were deactivated")) << e.what();
    EXPECT_TRUE(contains(e.what(), "controller 'test_pd': injected deactivate failure")) << e.what();
    EXPECT_FALSE(contains(e.what(), "disable() threw")) << e.what();
  }
}

TEST(DeviceLifecycle, TheSimulatedDeviceIsHomedAndDescribesItsCapabilities) {
  Session s = test::build_test_session(test::sim_vishard3_admittance_session("v3", 3));
  s.step(10);
  EXPECT_EQ(s.device("v3").fault, "");
  std::string yaml = test::sim_vishard3_admittance_session("v3", 3);
  yaml.replace(yaml.find("passive_gimbal: true"), 20,
               "passive_gimbal: true\n        homing: true\n        brakes: true");
  Session homed = test::build_test_session(yaml);
  const DeviceDescription& d = homed.impl().devices[0]->description();
  EXPECT_TRUE(d.capabilities.homing);
  EXPECT_TRUE(d.capabilities.brakes);
  homed.step(10);
  EXPECT_EQ(homed.device("v3").fault, "");
  // Homed: the same absolute positions as the device without homing.
  EXPECT_LT((homed.device("v3").state.joints.position - s.device("v3").state.joints.position).norm(), 1e-9);
}

}  // namespace
}  // namespace hapticd::server
