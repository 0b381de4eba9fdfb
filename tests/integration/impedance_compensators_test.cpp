// The impedance controller's friction compensators on the simulated ViSHaRD3 in lockstep: the
// variable-structure controller against static friction, the disturbance observer, joint-torque feedback,
// and allocation-free updates for every variant.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/friction_model.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "joint_friction.hpp"
#include "support/test_paths.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;

// The force a scripted push needs to start the handle moving from rest: the push ramps at 4 N/s along x
// and the break-away force is the push when the handle has moved 2 mm. Returns 1e9 if it never moves in 10 s.
double breakaway_force(const std::string& controller_parameters) {
  const std::string yaml = "server: {clock: lockstep, seed: 5}\ndevices:\n" +
                           test::sim_vishard3_device_yaml("v3", "ramp", "[4.0, 0.0, 0.0]") + R"(        warm_up: false
    controller:
      plugin: impedance
      parameters: {task: translation, )" +
                           controller_parameters + "}\n";
  auto s = test::build_test_session(yaml);
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  d.cycle(cycle_at(0), 1.0);
  const Eigen::Vector3d start = d.chain_state().handle_pose.position;
  for (std::uint64_t k = 1; k < 20000; ++k) {
    d.cycle(cycle_at(k), 1.0);
    EXPECT_EQ(d.status().fault(), DeviceFault::none);
    if ((d.chain_state().handle_pose.position - start).norm() > 0.002) return 4.0 * static_cast<double>(k) * 5e-4;
  }
  return 1e9;
}

TEST(StictionCompensation, VariableStructureControlRemovesMostOfTheBreakAwayForce) {
  const double open_loop = breakaway_force("force_gain: 0");
  const double force_feedback = breakaway_force("force_gain: 3");
  const double variable_structure =
      breakaway_force("force_gain: 3, friction_compensation: true, stiction_compensation: true");
  RecordProperty("breakaway_open_loop_n", std::to_string(open_loop));
  RecordProperty("breakaway_force_feedback_n", std::to_string(force_feedback));
  RecordProperty("breakaway_variable_structure_n", std::to_string(variable_structure));
  std::printf("break-away force: open loop %.2f N, PD Kp=3 %.2f N, variable structure %.2f N\n", open_loop,
              force_feedback, variable_structure);
  EXPECT_GT(open_loop, 2.0) << "the simulated stiction must hold the handle";
  // Stated bound: "most" = at most a quarter of the open-loop break-away force, and clearly below PD.
  EXPECT_LT(variable_structure, 0.25 * open_loop);
  EXPECT_LT(variable_structure, 0.7 * force_feedback);
}

// The sliding friction of the simulated joints (friction_variation 0: all alike) at time t of the warm-up.
double true_sliding_friction(double speed, double time_s, double warm_up_time_constant_s) {
  sim::FrictionParameters p;
  p.warm_up_time_constant_s = warm_up_time_constant_s;
  p.load_dependent = false;
  sim::JointFriction f;
  f.configure(p, 1);
  f.advance_temperature(time_s);
  return f.sliding_magnitude(speed, 0.0);
}

struct RetuneRow {
  double time_s;
  int joint;
  bool accepted;
  model::FrictionModel model;
};

std::vector<RetuneRow> read_retune_log(const std::string& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // header
  std::vector<RetuneRow> rows;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    RetuneRow r{};
    char c = 0;
    int accepted = 0, bins = 0;
    ss >> r.time_s >> c >> r.joint >> c >> accepted >> c >> bins;
    for (double& p : r.model.p) ss >> c >> p;
    ss >> c >> r.model.velocity_max;
    r.accepted = accepted != 0;
    rows.push_back(r);
  }
  return rows;
}

TEST(AdaptiveFriction, ConvergesWhileTheJointsWarmUpAndNeverOverCompensates) {
  // 120 s with the operator moving the handle (8 cm, 6 cm at 0.7 Hz) while the simulated gears warm up from
  // the 26 C towards the 36 C curve (time constant 40 s); the compensator starts from the 26 C curve and
  // re-tunes every 10 s.
  constexpr double kWarmUp = 40.0;
  const std::string log = ::testing::TempDir() + "adaptive_friction.csv";
  const std::string yaml = test::sim_vishard3_session_head("v3", 11) + R"(        friction_variation: 0.0
        warm_up_time_constant_s: 40.0
        attachment: operator
        operator_grasp: 0.7
        operator_motion: sine
        operator_motion_m: [0.08, 0.06, 0.05]
        operator_motion_frequency_hz: 0.7
    controller:
      plugin: impedance
      parameters: {task: translation, force_gain: 3, friction_compensation: true, adaptive_friction: true,
                   adaptive_update_s: 10, adaptive_log: )" +
                           log + R"(}
)";
  {
    auto s = test::build_test_session(yaml);
    DeviceSession& d = *s.impl().devices[0];
    d.activate();
    for (std::uint64_t k = 0; k < 240000; ++k) {
      d.cycle(cycle_at(k), 1.0);
      ASSERT_EQ(d.status().fault(), DeviceFault::none) << "cycle " << k;
    }
  }  // the controller (and its worker) ends here: the log is complete
  const std::vector<RetuneRow> rows = read_retune_log(log);
  ASSERT_GE(rows.size(), 3u * 10u) << "a fit per joint every 10 s";

  const model::FrictionModel initial{{1.183, 1.008, -0.2642, 0.0487, -0.0037}, {0.0, 0.02, 0.0}, 5.0, 0.0};
  const double fraction = 0.8;
  int accepted = 0;
  std::array<double, 3> final_error{}, initial_error{};
  for (const RetuneRow& r : rows) {
    if (!r.accepted) continue;
    ++accepted;
    for (double v = 0.1; v <= std::min(0.8, r.model.velocity_max); v += 0.1) {
      const double truth = true_sliding_friction(v, r.time_s, kWarmUp);
      // Never over-compensates: what is compensated stays below the friction present at that time.
      EXPECT_LE(fraction * r.model.sliding(v), truth)
          << "joint " << r.joint << " at " << r.time_s << " s, " << v << " rad/s";
    }
  }
  EXPECT_GE(accepted, 3 * 5) << "most fits are accepted with this excitation";
  for (int j = 0; j < 3; ++j) {
    const RetuneRow* last = nullptr;
    for (const RetuneRow& r : rows)
      if (r.joint == j && r.accepted) last = &r;
    ASSERT_NE(last, nullptr) << "joint " << j;
    for (double v = 0.1; v <= 0.5; v += 0.1) {
      const double truth = true_sliding_friction(v, last->time_s, kWarmUp);
      final_error[static_cast<std::size_t>(j)] += std::abs(last->model.sliding(v) - truth) / truth / 5.0;
      initial_error[static_cast<std::size_t>(j)] += std::abs(initial.sliding(v) - truth) / truth / 5.0;
    }
    std::printf(
        "joint %d at %.0f s: mean relative error of the sliding friction 0.1..0.5 rad/s: start curve %.1f %%, "
        "re-tuned %.1f %%\n",
        j, last->time_s, 100 * initial_error[static_cast<std::size_t>(j)],
        100 * final_error[static_cast<std::size_t>(j)]);
    RecordProperty("adaptive_error_joint" + std::to_string(j) + "_percent",
                   std::to_string(100 * final_error[static_cast<std::size_t>(j)]));
    // Converges towards the warmed-up friction: closer than the start curve, and within 15 %.
    EXPECT_LT(final_error[static_cast<std::size_t>(j)], initial_error[static_cast<std::size_t>(j)]);
    EXPECT_LT(final_error[static_cast<std::size_t>(j)], 0.15);
  }
}

TEST(ImpedanceCompensators, EveryVariantUpdatesWithoutAllocating) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  const std::string variants[] = {
      "force_gain: 3, friction_compensation: true, stiction_compensation: true",
      "disturbance_observer: true, observer_nominal_inertia: 0.5",
      "joint_torque_gain: 2",
      // adaptive, with hand-overs to the worker and parameter updates inside the counted cycles
      "force_gain: 3, friction_compensation: true, adaptive_friction: true, adaptive_update_s: 0.1",
      "force_gain: 3, notch_hz: 64, friction_compensation: true, friction_file: " + hapticd::test::source_dir() +
          "/config/friction/vishard3.yaml",
  };
  for (const std::string& v : variants) {
    const std::string yaml = "server: {clock: lockstep, seed: 5}\ndevices:\n" +
                             test::sim_vishard3_device_yaml("v3", "sine", "[3.0, 2.0, 1.0]") +
                             "        joint_torque_sensors: true\n    controller:\n      plugin: impedance\n"
                             "      parameters: {task: translation, " +
                             v + "}\n";
    auto s = test::build_test_session(yaml);
    EXPECT_EQ(test::allocations_over_cycles(*s.impl().devices[0], 2000), 0u) << v;
    EXPECT_EQ(s.impl().devices[0]->status().fault(), DeviceFault::none) << v;
  }
}

}  // namespace
}  // namespace hapticd::server
