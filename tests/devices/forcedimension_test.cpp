// The forcedimension plugin and the handle-device chain, against the project's stand-in for Force Dimension's SDK
// (tests/standins/forcedimension), in lockstep: the stand-in's handle advances one loop period per force call, a
// simulated hand pushes it. The plugin loads the stand-in by path, as it would load the vendor's libdrd.so; the
// test loads the same file to set the scene, so both see the same devices.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "config/config_error.hpp"
#include "hapticd/server/session.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "support/test_paths.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

// The stand-in's controls (its test functions, not the vendor's).
struct StandIn {
  void* handle = nullptr;
  void (*setup)(const char*) = nullptr;
  void (*set_step)(double) = nullptr;
  bool (*fault)(int, const char*) = nullptr;
  bool (*hand)(int, double, double, double, unsigned) = nullptr;
  bool (*force)(int, double*, double*, double*) = nullptr;
  const char* (*call_log)() = nullptr;

  static std::string path() { return test::standin_dir() + "/forcedimension/libdrd.so"; }
  StandIn() {
    handle = dlopen(path().c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) return;
    setup = reinterpret_cast<decltype(setup)>(dlsym(handle, "standin_dhd_setup"));
    set_step = reinterpret_cast<decltype(set_step)>(dlsym(handle, "standin_dhd_set_step"));
    fault = reinterpret_cast<decltype(fault)>(dlsym(handle, "standin_dhd_fault"));
    hand = reinterpret_cast<decltype(hand)>(dlsym(handle, "standin_dhd_hand"));
    force = reinterpret_cast<decltype(force)>(dlsym(handle, "standin_dhd_force"));
    call_log = reinterpret_cast<decltype(call_log)>(dlsym(handle, "standin_dhd_call_log"));
  }
  ~StandIn() {
    if (handle != nullptr) dlclose(handle);
  }
  StandIn(const StandIn&) = delete;
  StandIn& operator=(const StandIn&) = delete;
  [[nodiscard]] Eigen::Vector3d written(int index) const {
    Eigen::Vector3d f;
    force(index, &f.x(), &f.y(), &f.z());
    return f;
  }
};

class ForceDimension : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_NE(standin_.handle, nullptr) << dlerror();
    standin_.setup("omega.6:10001,omega.7:10002");
    standin_.set_step(0.0005);  // one loop period per force call: lockstep
  }

  // A lockstep session of one device entry per `devices` text (each "- name: ..." with its chain).
  static std::string session(const std::string& devices) {
    return "server: {rate_hz: 2000, clock: lockstep, seed: 3}\ndevices:\n" + devices;
  }
  // The SDK calls' deadline: a second, unless the test sets its own (a sanitizer's run on a loaded machine can delay
  // the SDK thread's wake-up past the default 20 ms; these tests test the plugin, not the machine).
  static std::string omega(const std::string& name, const std::string& device_parameters, const std::string& chain) {
    const std::string deadline =
        device_parameters.find("call_deadline_ms") == std::string::npos ? ", call_deadline_ms: 1000" : "";
    return "  - name: " + name +
           "\n    device:\n      plugin: forcedimension\n      parameters: {sdk_path: " + StandIn::path() + deadline +
           (device_parameters.empty() ? "" : ", " + device_parameters) + "}\n" + chain;
  }
  // Impedance display of a wall 5 mm ahead of the start along +x (its free side -x), 2000 N/m.
  static std::string wall_chain() {
    return "    virtual_model:\n      plugin: scripted_wrench\n"
           "      parameters: {display: impedance, force_n: [0, 0, 0], walls: [0.005, 0, 0, -1, 0, 0],\n"
           "                   wall_stiffness_n_per_m: 2000, wall_damping_n_s_per_m: 5}\n"
           "    controller: {plugin: handle_force}\n";
  }

  static std::string config_error(const std::string& yaml) { return test::config_error_of(yaml); }

  StandIn standin_;
};

TEST_F(ForceDimension, AWallInImpedanceDisplayHoldsTheHandAndTheButtonsArrive) {
  Session s = test::build_test_session(session(omega("left", "index: 0", wall_chain())));
  standin_.hand(0, 2.0, 0.0, 0.0, 0x1);  // the hand pushes 2 N along +x, its button held
  s.step(4000);                          // 2 s
  const DeviceView v = s.device("left");
  ASSERT_EQ(v.fault, "");
  // The wall at 5 mm balances the 2 N push: 1 mm deep at 2000 N/m, still (the handle's own damping, the wall's).
  EXPECT_NEAR(v.handle_pose.position.x(), 0.006, 3e-4);
  EXPECT_NEAR(standin_.written(0).x(), -2.0, 0.05);
  EXPECT_LT(v.handle_twist.linear.norm(), 1e-3);
  // A handle device's axes are the handle's: x, y, z of an omega.6 (its orientation sensed, not actuated).
  ASSERT_EQ(v.state.joints.position.size(), 3);
  EXPECT_DOUBLE_EQ(v.state.joints.position.x(), v.state.handle.pose.position.x());
  EXPECT_DOUBLE_EQ(v.command.torque_nm.x(), standin_.written(0).x());
  EXPECT_EQ(v.state.handle.buttons, 0x1u);
  // What the unit is, as the server logs it at start: its serial number and the SDK's version and file.
  const DeviceDescription& d = s.impl().devices[0]->description();
  EXPECT_EQ(d.serial, "10001");
  EXPECT_EQ(d.vendor_software, "Force Dimension SDK 3.6.0, " + StandIn::path());
}

TEST_F(ForceDimension, TwoDevicesOpenBySerialNumberAndTheGripperIsAnAxis) {
  Session s = test::build_test_session(
      session(omega("left", "serial: 10001", wall_chain()) + omega("right", "serial: 10002", wall_chain())));
  s.step(1);
  // The gripper's first sample has no rate (not its opening over one period, a jump the safe mode would damp).
  EXPECT_EQ(s.device("right").state.joints.velocity[3], 0.0);
  standin_.hand(1, 2.0, 0.0, 0.0, 0);
  s.step(2000);
  EXPECT_EQ(s.device("left").fault, "");
  const DeviceView right = s.device("right");
  EXPECT_EQ(right.fault, "");
  EXPECT_EQ(right.state.joints.position.size(), 4);               // x, y, z, gripper (omega.7)
  EXPECT_NEAR(right.state.joints.position[3], 0.3, 1e-12);        // the stand-in's gripper opening
  EXPECT_GT(right.handle_pose.position.x(), 0.005);               // the one pushed is at its wall
  EXPECT_LT(s.device("left").handle_pose.position.norm(), 1e-9);  // the other did not move
}

TEST_F(ForceDimension, ChainStagesThatNeedJointsAreConfigErrorsNamingTheirKey) {
  const std::string ik = config_error(session(
      omega("left", "", "    inverse_kinematics: {plugin: newton_ik}\n    controller: {plugin: handle_force}\n")));
  EXPECT_NE(ik.find("inverse_kinematics"), std::string::npos) << ik;
  EXPECT_NE(ik.find("handle device"), std::string::npos) << ik;
  const std::string controller = config_error(session(omega("left", "", "    controller: {plugin: impedance}\n")));
  EXPECT_NE(controller.find("controller.plugin"), std::string::npos) << controller;
  EXPECT_NE(controller.find("handle_force"), std::string::npos) << controller;
}

TEST_F(ForceDimension, AnUncalibratedDeviceIsRefusedUnlessTheSessionAsksToCalibrateIt) {
  standin_.fault(0, "uncalibrated");
  try {
    (void)test::build_test_session(session(omega("left", "", wall_chain())));
    FAIL() << "an uncalibrated device was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("not calibrated"), std::string::npos) << e.what();
  }
  Session s = test::build_test_session(session(omega("left", "calibrate: true", wall_chain())));
  s.step(10);
  EXPECT_EQ(s.device("left").fault, "");
  EXPECT_NE(std::string(standin_.call_log()).find("drdAutoInit(0)"), std::string::npos) << standin_.call_log();
}

TEST_F(ForceDimension, AnUnpluggedDeviceFaultsWithTheVendorsTextAndIsBrakedAtRest) {
  Session s = test::build_test_session(session(omega("left", "", wall_chain())));
  s.step(1000);
  standin_.fault(0, "unplug");
  s.step(10);
  const DeviceView v = s.device("left");
  EXPECT_NE(v.fault.find("communication error"), std::string::npos) << v.fault;  // the SDK's own words
  standin_.fault(0, "replug");
  s.step(2000);  // the safe mode's damping phase ends: at rest, the brakes engage
  EXPECT_TRUE(s.device("left").at_rest);
  const std::string log = standin_.call_log();
  EXPECT_NE(log.find("dhdSetBrakes(on)"), std::string::npos) << log;
}

TEST_F(ForceDimension, TheLifecycleRunsInTheVendorsOrder) {
  // Open and check the calibration (configure); the gravity compensation, forces on and the brakes released
  // (enable); cycles; at the end forces off, the brakes engaged and the device closed.
  {
    Session s = test::build_test_session(session(omega("left", "", wall_chain())));
    s.step(100);
  }
  const std::string log = standin_.call_log();
  const std::vector<std::string> order = {"dhdOpen(0)",
                                          "drdIsInitialized(0)",
                                          "dhdSetGravityCompensation(on)(0)",
                                          "dhdEnableForce(on)(0)",
                                          "dhdSetBrakes(off)(0)",
                                          "dhdEnableForce(off)(0)",
                                          "dhdSetBrakes(on)(0)",
                                          "dhdClose(0)"};
  std::size_t at = 0;
  for (const std::string& call : order) {
    const std::size_t found = log.find(call + "\n", at);
    ASSERT_NE(found, std::string::npos) << call << " missing after position " << at << " in:\n" << log;
    at = found + call.size();
  }
}

TEST_F(ForceDimension, ADeviceThatIsNotThereIsSaidSoBeforeAnythingIsPowered) {
  std::string e = config_error(session(omega("left", "serial: 99999", wall_chain())));
  EXPECT_NE(e.find("no Force Dimension device with serial number 99999 (2 connected)"), std::string::npos) << e;
  e = config_error(session(omega("left", "index: 5", wall_chain())));
  EXPECT_NE(e.find("no Force Dimension device with index 5"), std::string::npos) << e;
  EXPECT_EQ(std::string(standin_.call_log()).find("dhdEnableForce(on)"), std::string::npos) << standin_.call_log();
}

TEST_F(ForceDimension, AnUnpluggedDeviceFaultsInItsCycleAndItsNeighbourRunsOn) {
  Session s = test::build_test_session(
      session(omega("left", "serial: 10001", wall_chain()) + omega("right", "serial: 10002", wall_chain())));
  standin_.hand(0, 2.0, 0.0, 0.0, 0);
  standin_.hand(1, 2.0, 0.0, 0.0, 0);
  s.step(2000);
  standin_.fault(0, "unplug");
  s.step(1);  // the cycle that meets the unplugged device faults it
  EXPECT_NE(s.device("left").fault.find("communication error"), std::string::npos) << s.device("left").fault;
  s.step(2000);
  EXPECT_EQ(s.device("right").fault, "");
  EXPECT_NEAR(standin_.written(1).x(), -2.0, 0.1);  // the right one still holds its hand at the wall
}

TEST_F(ForceDimension, TheRenderedForceIsCappedAndItsRateLimited) {
  // A scripted 10 N step on a device whose safety caps the rendered force at 4 N and its rate at 400 N/s: the
  // force written climbs at most 0.2 N a period (2 kHz) and stops at 4 N.
  const std::string chain =
      "    virtual_model:\n      plugin: scripted_wrench\n"
      "      parameters: {display: impedance, signal: constant, force_n: [10, 0, 0]}\n"
      "    controller: {plugin: handle_force}\n"
      "    safety: {max_force_n: 4, max_force_rate_n_per_s: 400, soft_start_s: 0}\n";
  Session s = test::build_test_session(session(omega("left", "", chain)));
  standin_.hand(0, -4.0, 0.0, 0.0, 0);  // the hand holds the handle against the capped force
  double previous = 0.0, largest_step = 0.0;
  for (int i = 0; i < 40; ++i) {  // 20 ms: the rate limit alone would reach 8 N, the cap stops it at 4 N
    s.step(1);
    const double now = standin_.written(0).x();
    largest_step = std::max(largest_step, std::abs(now - previous));
    previous = now;
  }
  EXPECT_LE(largest_step, 400.0 / 2000.0 + 1e-9);
  s.step(200);
  EXPECT_NEAR(standin_.written(0).x(), 4.0, 1e-6);
  EXPECT_EQ(s.device("left").fault, "");
}

TEST_F(ForceDimension, AnEmergencyStopZeroesTheForceBrakesAndRecoversOnRequest) {
  Session s = test::build_test_session(session(omega("left", "", wall_chain())));
  standin_.hand(0, 2.0, 0.0, 0.0, 0);
  s.step(2000);
  ASSERT_NEAR(standin_.written(0).x(), -2.0, 0.1);
  ASSERT_TRUE(s.request("left", {DeviceRequest::Kind::emergency_stop, "", {}}).accepted);
  standin_.hand(0, 0.0, 0.0, 0.0, 0);
  s.step(2000);
  EXPECT_EQ(standin_.written(0).norm(), 0.0);
  EXPECT_TRUE(s.device("left").at_rest);
  std::string log = standin_.call_log();
  EXPECT_NE(log.find("dhdSetBrakes(on)"), std::string::npos) << log;
  ASSERT_TRUE(s.request("left", {DeviceRequest::Kind::recover, "", {}}).accepted);
  s.step(100);
  EXPECT_EQ(s.device("left").fault, "");
  log = standin_.call_log();
  EXPECT_NE(log.rfind("dhdSetBrakes(off)"), std::string::npos);
  EXPECT_GT(log.rfind("dhdSetBrakes(off)"), log.rfind("dhdSetBrakes(on)")) << log;  // released to run again
  // Disabled at the end: forces off, brakes on.
}

TEST_F(ForceDimension, TheSafetyWorkspaceIsTheDevicesOwnAndPushesBack) {
  // No wall of the model: the hand pushes the handle towards the end of the omega's box (x 55 mm); the safety
  // layer's walls (3000 N/m) take it from there.
  const std::string free_space = "    controller: {plugin: handle_force}\n";
  Session s = test::build_test_session(
      session(omega("left", "", free_space) + "    safety: {speed_damping_from_m_s: 0.2, max_speed_m_s: 3}\n"));
  standin_.hand(0, 3.0, 0.0, 0.0, 0);
  s.step(6000);
  const DeviceView v = s.device("left");
  EXPECT_EQ(v.fault, "");
  EXPECT_NEAR(v.handle_pose.position.x(), 0.055 + 3.0 / 3000.0, 3e-4);
  EXPECT_NEAR(standin_.written(0).x(), -3.0, 0.1);
}

TEST_F(ForceDimension, AMotionSourceRunsThroughATaskSpacePositionLoop) {
  // An admittance-type model (the desired motion: a 10 mm step along x after 0.5 s) on a device that takes forces:
  // the controller's position loop (3000 N/m, 20 N s/m) tracks it.
  const std::string trajectory =
      "    virtual_model:\n      plugin: trajectory\n"
      "      parameters: {path: step, path_m: [0.01, 0, 0], path_start_s: 0.5}\n"
      "    controller: {plugin: handle_force, parameters: {stiffness_n_per_m: 3000, damping_n_s_per_m: 20}}\n";
  Session s = test::build_test_session(session(omega("left", "", trajectory)));
  s.step(4000);
  EXPECT_EQ(s.device("left").fault, "");
  EXPECT_NEAR(s.device("left").handle_pose.position.x(), 0.01, 1e-4);
  standin_.hand(0, 1.0, 0.0, 0.0, 0);  // a hand against the loop: held 1 N / 3000 N/m off
  s.step(4000);
  const DeviceView v = s.device("left");
  EXPECT_EQ(v.fault, "");
  EXPECT_NEAR(v.handle_pose.position.x(), 0.01 + 1.0 / 3000.0, 5e-5);
}

TEST_F(ForceDimension, AdmittanceDisplayWithoutAForceSensorIsAConfigErrorSayingWhy) {
  const std::string e = config_error(session(omega("left", "",
                                                   "    virtual_model: {plugin: admittance, parameters: {mass_kg: "
                                                   "[1, 1, 1]}}\n    controller: {plugin: handle_force}\n")));
  EXPECT_NE(e.find("virtual_model.parameters.mass_kg"), std::string::npos) << e;
  EXPECT_NE(e.find("no operator force"), std::string::npos) << e;
}

// Round 4: an SDK call that never returns (a USB transfer that hangs) held the loop: every dhd call ran on the loop's
// thread with no deadline, so the whole session - the other device too - stopped, with no fault and no reason.
TEST_F(ForceDimension, ACallThatHangsFaultsItsDeviceNamingTheCallAndTheOtherDeviceRunsOn) {
  Session s = test::build_test_session(session(omega("left", "serial: 10001, call_deadline_ms: 200", wall_chain()) +
                                               omega("right", "serial: 10002", wall_chain())));
  standin_.hand(0, 2.0, 0.0, 0.0, 0);
  standin_.hand(1, 2.0, 0.0, 0.0, 0);
  s.step(2000);
  ASSERT_EQ(s.device("left").fault, "");
  standin_.fault(0, "hang_position");  // the left one's next dhdGetPosition does not return
  s.step(2000);                        // 1 s of the session: each cycle waits at most the deadline, once
  const std::string fault = s.device("left").fault;
  EXPECT_NE(fault.find("has not returned from dhdGetPosition"), std::string::npos) << fault;
  EXPECT_NE(fault.find("call_deadline_ms"), std::string::npos) << fault;
  EXPECT_EQ(s.device("right").fault, "");
  EXPECT_NEAR(standin_.written(1).x(), -2.0, 0.1);  // the right one still holds its hand at the wall
  // A recovery while the call is still out is refused, saying why.
  ASSERT_TRUE(s.request("left", {DeviceRequest::Kind::recover, "", {}}).accepted);
  s.step(10);
  EXPECT_NE(s.device("left").fault, "");
  // The call returns: the device comes to rest in its safe mode, brakes, and recovers on request.
  standin_.fault(0, "release");
  standin_.hand(0, 0.0, 0.0, 0.0, 0);
  s.step(4000);
  EXPECT_TRUE(s.device("left").at_rest);
  ASSERT_TRUE(s.request("left", {DeviceRequest::Kind::recover, "", {}}).accepted);
  s.step(100);
  EXPECT_EQ(s.device("left").fault, "");
}

TEST_F(ForceDimension, OpeningADeviceThatDoesNotAnswerIsGivenUpAtItsTimeoutNamingTheCall) {
  standin_.fault(0, "hang_open");
  const std::string e = config_error(session(omega("left", "open_timeout_s: 0.2", wall_chain())));
  EXPECT_NE(e.find("did not return from dhdOpenID within open_timeout_s"), std::string::npos) << e;
  // The call the server gave up returns later, into nothing freed, and closes the device it opened.
  standin_.fault(0, "release");
  for (int i = 0; i < 500 && std::string(standin_.call_log()).find("dhdClose(0)") == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_NE(std::string(standin_.call_log()).find("dhdClose(0)"), std::string::npos) << standin_.call_log();
  EXPECT_EQ(config_error(session(omega("left", "", wall_chain()))), "");
}

TEST_F(ForceDimension, TheCycleAllocatesNothing) {
  Session s = test::build_test_session(session(omega("left", "", wall_chain())));
  standin_.hand(0, 2.0, 0.0, 0.0, 0);
  EXPECT_EQ(test::allocations_over_cycles(test::device_of(s), 2000), 0u);
}

}  // namespace
}  // namespace hapticd::server
