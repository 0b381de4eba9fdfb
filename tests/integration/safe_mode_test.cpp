// The safe mode of devices with a robot model (lockstep, the shipped sessions of the simulated ViSHaRD3, 6
// and 10): after an E-stop with the operator's hand off, the gravity-holding safe mode keeps the handle where
// it was, the measured state goes on being published (an arm that sags is seen), and a recovery starts from
// the measured state without a torque step.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "session/device_requests.hpp"
#include "session/device_session.hpp"
#include "support/test_paths.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;

// A shipped session file, in lockstep, with its relative model paths made absolute and `safety` added.
std::string shipped_session(const std::string& file, const std::string& safety) {
  std::ifstream in(hapticd::test::source_dir() + "/config/sessions/" + file);
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  for (const std::string folder : {"urdf/", "friction/"}) {  // the session's relative paths, made absolute
    for (std::size_t at; (at = yaml.find("../../" + folder)) != std::string::npos;)
      yaml.replace(at, 6 + folder.size(), hapticd::test::source_dir() + "/config/" + folder);
  }
  for (std::size_t at; (at = yaml.find("clock: realtime")) != std::string::npos;)
    yaml.replace(at, 15, "clock: lockstep");
  return yaml + "    safety: {" + safety + "}\n";
}

struct SafeModeRun {
  double largest_sag_m = 0.0;             // handle displacement (true pose) during the 2 s after the stop
  double published_sag_m = 0.0;           // the same, as the published state (snapshots) shows it
  double largest_recovery_step_nm = 0.0;  // torque step per cycle in the 100 ms after the recovery
  double largest_running_step_nm = 0.0;   // the same over the 0.5 s before the stop (normal running)
  DeviceFault final_fault = DeviceFault::none;
  std::uint64_t recoveries = 0;
};

// Runs 1 s, stops (E-stop) and takes the operator's hand off, watches 2 s of safe mode, asks for a recovery
// and runs 0.5 s more.
SafeModeRun stop_hold_and_recover(const std::string& yaml) {
  auto s = test::build_test_session(yaml);
  DeviceSession& d = *s.impl().devices[0];
  d.set_snapshot_interval(1);
  d.activate();
  SafeModeRun r;
  const std::uint64_t stop = 2000, recover = 6000, end = 7000;
  Eigen::Vector3d at_stop = Eigen::Vector3d::Zero(), published_at_stop = Eigen::Vector3d::Zero();
  JointVector previous;
  DeviceSnapshot snapshot;
  std::uint64_t recovered_at = 0;
  for (std::uint64_t k = 0; k < end; ++k) {
    if (k == stop) {
      d.requests().emergency_stop();
      EXPECT_TRUE(d.requests().apply({DeviceRequest::Kind::drive_operator, "release", {}}).accepted);
    }
    if (k == recover) {
      EXPECT_TRUE(d.requests().recover().accepted);
    }
    d.cycle(cycle_at(k), 1.0);
    d.service();
    const bool have_snapshot = d.status().take_snapshot(snapshot);
    const JointVector& torque = d.command().torque_nm;
    if (k > 0) {
      const double step = (torque - previous).cwiseAbs().maxCoeff();
      if (k + 1000 >= stop && k < stop) r.largest_running_step_nm = std::max(r.largest_running_step_nm, step);
      if (recovered_at > 0 && k < recovered_at + 200)
        r.largest_recovery_step_nm = std::max(r.largest_recovery_step_nm, step);
    }
    previous = torque;
    if (recovered_at == 0 && k > recover && d.status().fault() == DeviceFault::none) recovered_at = k;
    const Eigen::Vector3d x = d.chain_state().handle_pose.position;
    if (k == stop) {
      at_stop = x;
      if (have_snapshot) published_at_stop = snapshot.handle_pose.position;
    }
    if (k > stop && k < recover) {
      EXPECT_EQ(d.status().fault(), DeviceFault::emergency_stop);
      r.largest_sag_m = std::max(r.largest_sag_m, (x - at_stop).norm());
      if (have_snapshot)
        r.published_sag_m = std::max(r.published_sag_m, (snapshot.handle_pose.position - published_at_stop).norm());
    }
  }
  r.final_fault = d.status().fault();
  r.recoveries = d.status().recoveries();
  d.deactivate();
  return r;
}

void expect_held(const std::string& file) {
  const SafeModeRun held = stop_hold_and_recover(shipped_session(file, ""));
  const SafeModeRun falls = stop_hold_and_recover(shipped_session(file, "gravity_hold: false"));
  std::printf(
      "%s: 2 s of safe mode, hand off: handle moved %.2f mm holding (published %.2f mm), %.1f mm with damping "
      "only (published %.1f mm); torque step after the recovery %.3f N m (running before the stop: %.3f)\n",
      file.c_str(), 1e3 * held.largest_sag_m, 1e3 * held.published_sag_m, 1e3 * falls.largest_sag_m,
      1e3 * falls.published_sag_m, held.largest_recovery_step_nm, held.largest_running_step_nm);
  EXPECT_LT(held.largest_sag_m, 0.005);
  // The published state is the measured one: it shows the hold, and it shows the fall without it.
  EXPECT_NEAR(held.published_sag_m, held.largest_sag_m, 1e-9);
  EXPECT_NEAR(falls.published_sag_m, falls.largest_sag_m, 1e-9);
  EXPECT_GT(falls.largest_sag_m, 0.02) << "without the hold the arm should sag (else this test shows nothing)";
  EXPECT_EQ(held.final_fault, DeviceFault::none);
  EXPECT_EQ(held.recoveries, 1u);
  // The recovery fades the holding torque into the chain's: no step beyond what the running chain does.
  EXPECT_LE(held.largest_recovery_step_nm, std::max(0.5, 2.0 * held.largest_running_step_nm));
}

TEST(SafeMode, GravityHoldKeepsTheViSHaRD3HandleStill) {
  expect_held("vishard3/admittance-resolved-acceleration.yaml");
}
TEST(SafeMode, GravityHoldKeepsTheViSHaRD6HandleStill) {
  expect_held("vishard6/admittance-resolved-acceleration.yaml");
}
TEST(SafeMode, GravityHoldKeepsTheViSHaRD10HandleStill) { expect_held("vishard10/admittance-pseudoinverse.yaml"); }

}  // namespace
}  // namespace hapticd::server
