// Admittance display on the simulated ViSHaRD10 (10 joints, 6-D task) in lockstep, with each redundancy
// resolution: forces and torques give the virtual mass's and inertia's accelerations in all six directions,
// and the self-motion stays bounded.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <vector>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/redundancy.hpp"
#include "hapticd/server/session.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "support/test_paths.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;
constexpr double kPi = 3.14159265358979323846;

// The SCARA folded, the wrist away from q9 = 0; the partitioned inverse functions' own posture for the handle
// at (0.2, 0.15, 1.45) with its axis vertical, and the look-up table's for (0.45, 0.1, 1.45) (the plugin refuses
// to start elsewhere).
constexpr const char* kFolded = "[0.8, -1.6, 1.6, -1.6, 0.8, 1.0, -2.0, 1.0, 1.3, 0.0]";
constexpr const char* kLookupTable =
    "[1.128695, -0.129132, -1.358170, -1.317278, 1.675886, -1.146954, 2.293908, -2.717751, 1.570796, 0.0]";
constexpr const char* kPartitioned =
    "[1.159279, -2.318559, 3.996179, -2.532207, -0.304693, -1.146954, 2.293908, -2.717751, 1.570796, 0.0]";

struct Scheme {
  const char* name;               // test label
  std::string ik;                 // the inverse_kinematics entry
  const char* controller;         // the controller entry
  double tolerance;               // relative, on the rendered acceleration
  const char* initial = kFolded;  // initial joint positions
};

const Scheme kSchemes[] = {
    {"pseudoinverse", "{plugin: redundancy_ik, parameters: {task: full, inverse: pseudoinverse}}",
     "{plugin: resolved_acceleration, parameters: {task: full, bandwidth_rad_s: 20, rotational_bandwidth_rad_s: 40}}",
     0.08},
    {"weighted",
     "{plugin: redundancy_ik, parameters: {task: full, inverse: weighted, joint_weights: [1, 1, 1, 1, 3, 1, 1, 0.2, 1, "
     "0.1]}}",
     "{plugin: resolved_acceleration, parameters: {task: full, bandwidth_rad_s: 20, rotational_bandwidth_rad_s: 40}}",
     0.08},
    {"damped", "{plugin: redundancy_ik, parameters: {task: full, inverse: damped, damping: 0.005}}",
     "{plugin: resolved_acceleration, parameters: {task: full, bandwidth_rad_s: 20, rotational_bandwidth_rad_s: 40}}",
     0.08},
    {"inertia_weighted", "{plugin: redundancy_ik, parameters: {task: full, inverse: inertia_weighted}}",
     "{plugin: resolved_acceleration, parameters: {task: full, bandwidth_rad_s: 20, rotational_bandwidth_rad_s: 40}}",
     0.08},
    {"torque_level", "{plugin: redundancy_ik, parameters: {task: full, inverse: inertia_weighted}}",
     "{plugin: transposed_jacobian, parameters: {task: full, bandwidth_rad_s: 20, rotational_bandwidth_rad_s: 40}}",
     0.08},
    {"velocity_level", "{plugin: redundancy_ik, parameters: {task: full, inverse: inertia_weighted, level: velocity}}",
     "{plugin: computed_torque, parameters: {task: full, bandwidth_rad_s: 30}}", 0.08},
    {"acceleration_level",
     "{plugin: redundancy_ik, parameters: {task: full, inverse: inertia_weighted, level: acceleration}}",
     "{plugin: computed_torque, parameters: {task: full, bandwidth_rad_s: 30}}", 0.08},
    // The handle axis stands vertical here: the rotation about it is joint 10's alone, whose friction the single
    // joint-space bandwidth (30 rad/s) leaves 9-11 % of the rendered inertia.
    {"partitioned", "{plugin: vishard10_ik}",
     "{plugin: computed_torque, parameters: {task: full, bandwidth_rad_s: 30}}", 0.12, kPartitioned},
    {"partitioned_wrist_pseudoinverse", "{plugin: vishard10_ik, parameters: {wrist: pseudoinverse}}",
     "{plugin: computed_torque, parameters: {task: full, bandwidth_rad_s: 30}}", 0.12, kPartitioned},
    {"partitioned_lookup_table",
     "{plugin: vishard10_ik, parameters: {scara: lookup_table, scara_table: " + hapticd::test::source_dir() +
         "/config/scara/vishard10.table}}",
     "{plugin: computed_torque, parameters: {task: full, bandwidth_rad_s: 30}}", 0.12, kLookupTable},
};

std::string vishard10_session(const Scheme& scheme, const std::string& force, const std::string& torque) {
  return std::string("server: {clock: lockstep, seed: 7}\ndevices:\n") +
         test::sim_wrench_step_device_yaml("v10", "vishard10", scheme.initial, force, torque) + R"(    virtual_model:
      plugin: admittance
      parameters: {mass_kg: [4, 4, 4], damping_n_s_per_m: [0, 0, 0], inertia_kg_m2: [0.1, 0.1, 0.1],
                   rotational_damping_n_m_s: [0, 0, 0]}
    inverse_kinematics: )" +
         scheme.ik + R"(
    controller: )" +
         scheme.controller + "\n";
}

struct Trace {
  std::vector<double> t;
  std::vector<Eigen::Vector3d> x, rotation, target_x, target_rotation;
  double largest_joint_speed = 0.0;
};

Trace run(server::Session& s, int cycles) {
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  Trace trace;
  Eigen::Quaterniond start = Eigen::Quaterniond::Identity();
  for (int k = 0; k < cycles; ++k) {
    d.cycle(cycle_at(static_cast<std::uint64_t>(k)), 1.0);
    EXPECT_EQ(d.status().fault(), DeviceFault::none) << "cycle " << k << ": " << to_string(d.status().fault());
    if (d.status().fault() != DeviceFault::none) break;
    if (k == 0) start = d.chain_state().handle_pose.orientation;
    trace.t.push_back(k * 5e-4);
    trace.x.push_back(d.chain_state().handle_pose.position);
    const Eigen::AngleAxisd r(d.chain_state().handle_pose.orientation * start.conjugate());
    trace.rotation.push_back(r.angle() * r.axis());
    const Eigen::AngleAxisd tr(d.task().pose.orientation * start.conjugate());
    trace.target_rotation.push_back(tr.angle() * tr.axis());
    trace.target_x.push_back(d.task().pose.position);
    trace.largest_joint_speed = std::max(trace.largest_joint_speed, d.state().joints.velocity.cwiseAbs().maxCoeff());
  }
  return trace;
}

// Least-squares x(t) = a0 + a1 t + a2 t^2 over [t0, t1] along `axis`: the acceleration 2 a2.
double acceleration(const Trace& trace, double t0, double t1, int axis, bool rotation, bool target = false) {
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < trace.t.size(); ++i)
    if (trace.t[i] >= t0 && trace.t[i] <= t1) rows.push_back(i);
  Eigen::MatrixXd a(static_cast<Eigen::Index>(rows.size()), 3);
  Eigen::VectorXd b(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const double t = trace.t[rows[r]] - t0;
    a.row(static_cast<Eigen::Index>(r)) << 1.0, t, t * t;
    const auto& series =
        target ? (rotation ? trace.target_rotation : trace.target_x) : (rotation ? trace.rotation : trace.x);
    b[static_cast<Eigen::Index>(r)] = series[rows[r]][axis];
  }
  return 2.0 * a.colPivHouseholderQr().solve(b)[2];
}

class RedundantAdmittance : public ::testing::TestWithParam<Scheme> {};

TEST_P(RedundantAdmittance, RendersTheVirtualMassAndInertiaInAllSixDirections) {
  const Scheme& scheme = GetParam();
  for (int direction = 0; direction < 6; ++direction) {
    const int axis = direction % 3;
    const bool rotation = direction >= 3;
    std::string force = "[0, 0, 0]", torque = "[0.0, 0.0, 0.0]";
    if (rotation) {
      torque.replace(static_cast<std::size_t>(1 + 5 * axis), 3, "0.1");  // 0.1 N m on 0.1 kg m^2: 1 rad/s^2
    } else {
      force[1 + 3 * axis] = '4';  // 4 N on 4 kg: 1 m/s^2
    }
    auto s = test::build_test_session(vishard10_session(scheme, force, torque));
    const Trace trace = run(s, 1200);
    ASSERT_EQ(trace.t.size(), 1200u);
    // The push starts at 0.2 s; fitted from 0.35 s, once the inner loop (20 rad/s) has caught up.
    const double measured = acceleration(trace, 0.35, 0.6, axis, rotation);
    std::printf("%-16s %s %c: %.3f %s (1.0 expected; target %.3f), largest joint speed %.2f rad/s\n", scheme.name,
                rotation ? "torque about" : "force along ", "xyz"[axis], measured, rotation ? "rad/s^2" : "m/s^2",
                acceleration(trace, 0.35, 0.6, axis, rotation, true), trace.largest_joint_speed);
    RecordProperty(std::string(rotation ? "angular_" : "linear_") + "xyz"[axis], std::to_string(measured));
    EXPECT_NEAR(measured, 1.0, scheme.tolerance)
        << scheme.name << (rotation ? " torque about " : " force along ") << "xyz"[axis];
  }
}

TEST_P(RedundantAdmittance, TheChainDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  auto s = test::build_test_session(vishard10_session(GetParam(), "[4, 0, 0]", "[0.0, 0.1, 0.0]"));
  EXPECT_EQ(test::allocations_over_cycles(*s.impl().devices[0], 1000), 0u);
}

TEST(RedundantSelfMotion, NeedsItsNullSpaceDamping) {
  // Resolved acceleration control fixes the task acceleration only: the self-motion is left to the null-space
  // term. Without its damping (d = 0) nothing holds it and it drifts away under the push; with the default
  // (20 /s) it stays small.
  const auto self_motion = [](const char* damping) {
    const std::string ik = std::string(
                               "{plugin: redundancy_ik, parameters: {task: full, inverse: pseudoinverse, "
                               "null_space_damping: ") +
                           damping + "}}";
    const Scheme scheme{"pseudoinverse", ik.c_str(), kSchemes[0].controller, 0.0};
    auto s = test::build_test_session(vishard10_session(scheme, "[4, 0, 0]", "[0.0, 0.0, 0.0]"));
    DeviceSession& d = *s.impl().devices[0];
    d.activate();
    model::GeneralizedInverse pinv;
    pinv.configure(model::InverseKind::pseudoinverse, 10, JointVector::Ones(10));
    double largest = 0.0;  // of the self-motion speed |(I - J^+ J) qd|
    for (std::uint64_t k = 0; k < 2000 && d.status().fault() == DeviceFault::none; ++k) {
      d.cycle(cycle_at(k), 1.0);
      pinv.compute(d.chain_state().data->frame_jacobian);
      largest = std::max(largest, (pinv.null_space_projector() * d.state().joints.velocity).norm());
    }
    return std::make_pair(largest, d.status().fault());
  };
  const auto [damped, damped_fault] = self_motion("20");
  const auto [free, free_fault] = self_motion("0");
  std::printf(
      "largest self-motion speed over 1 s: %.3f rad/s with null-space damping, %.3f rad/s without (fault: %s)\n",
      damped, free, std::string(fault_code(free_fault)).c_str());
  EXPECT_EQ(damped_fault, DeviceFault::none);
  EXPECT_TRUE(free_fault != DeviceFault::none || free > 3.0 * damped);
}

TEST(RedundantSelfMotion, TheWristCriterionMovesTheDeviceNotJustItsTarget) {
  // Resolved acceleration control with the wrist criterion in the null space and nobody pushing: the device's
  // own joint 9 (1.3 rad at the start) goes towards pi/2 while the handle holds its pose - the self-motion of
  // the measured arm, not only of the IK's integrated target. (With null_space_gain 1 the drives' stiction held
  // joint 9 where it was for the whole 2 s: the self-motion servo has no position memory.)
  const Scheme scheme{
      "wrist",
      "{plugin: redundancy_ik, parameters: {task: full, inverse: pseudoinverse, wrist: 1.0, null_space_gain: 10}}",
      kSchemes[0].controller, 0.0};
  auto s = test::build_test_session(vishard10_session(scheme, "[0, 0, 0]", "[0.0, 0.0, 0.0]"));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  d.cycle(cycle_at(0), 1.0);
  const double q9_start = d.state().joints.position[8];
  const Pose start = d.chain_state().handle_pose;
  for (std::uint64_t k = 1; k < 4000; ++k) d.cycle(cycle_at(k), 1.0);
  ASSERT_EQ(d.status().fault(), DeviceFault::none);
  const double q9_end = d.state().joints.position[8];
  const Pose& end = d.chain_state().handle_pose;
  const double moved = (end.position - start.position).norm();
  const double turned = Eigen::AngleAxisd(end.orientation * start.orientation.conjugate()).angle();
  std::printf("wrist criterion under RAC: q9 %.3f -> %.3f rad in 2 s (target pi/2); handle moved %.2f mm, %.4f rad\n",
              q9_start, q9_end, 1e3 * moved, turned);
  EXPECT_LT(std::abs(q9_end - kPi / 2), 0.5 * std::abs(q9_start - kPi / 2));
  EXPECT_LT(moved, 2e-3);
  EXPECT_LT(turned, 0.01);
}

TEST(RedundantSelfMotion, TheNullSpaceGainIsTunedAtRunTime) {
  // The same device and criterion with null_space_gain 1 (the drives' stiction holds joint 9), then a run-time
  // request "inverse_kinematics.null_space_gain" = 10 through the device: joint 9 now goes towards pi/2.
  const Scheme scheme{"wrist", "{plugin: redundancy_ik, parameters: {task: full, inverse: pseudoinverse, wrist: 1.0}}",
                      kSchemes[0].controller, 0.0};
  auto s = test::build_test_session(vishard10_session(scheme, "[0, 0, 0]", "[0.0, 0.0, 0.0]"));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  for (std::uint64_t k = 0; k < 2000; ++k) d.cycle(cycle_at(k), 1.0);
  const double q9_untuned = d.state().joints.position[8];
  const RuntimeReply tuned =
      s.request("v10", {DeviceRequest::Kind::set_parameter, "inverse_kinematics.null_space_gain", {10.0}});
  ASSERT_TRUE(tuned.accepted) << tuned.message;
  const RuntimeReply read =
      s.request("v10", {DeviceRequest::Kind::get_parameter, "inverse_kinematics.null_space_gain", {}});
  ASSERT_TRUE(read.accepted) << read.message;
  EXPECT_EQ(read.values, std::vector<double>{10.0});
  for (std::uint64_t k = 2000; k < 6000; ++k) d.cycle(cycle_at(k), 1.0);
  ASSERT_EQ(d.status().fault(), DeviceFault::none);
  const double q9_tuned = d.state().joints.position[8];
  std::printf("null-space gain tuned at run time: q9 1.300 -> %.3f rad (gain 1, 1 s) -> %.3f rad (gain 10, 2 s)\n",
              q9_untuned, q9_tuned);
  EXPECT_LT(std::abs(q9_untuned - 1.3), 0.05);
  EXPECT_LT(std::abs(q9_tuned - kPi / 2), 0.5 * std::abs(q9_untuned - kPi / 2));
  // A parameter the plugin does not declare tunable is refused, and names the tunable ones.
  const RuntimeReply fixed =
      s.request("v10", {DeviceRequest::Kind::set_parameter, "inverse_kinematics.damping", {0.1}});
  EXPECT_FALSE(fixed.accepted);
  EXPECT_NE(fixed.message.find("null_space_damping"), std::string::npos) << fixed.message;
}

INSTANTIATE_TEST_SUITE_P(IkPlugins, RedundantAdmittance, ::testing::ValuesIn(kSchemes),
                         [](const ::testing::TestParamInfo<Scheme>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace hapticd::server
