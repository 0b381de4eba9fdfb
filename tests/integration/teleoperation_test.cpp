// Bilateral teleoperation in lockstep (docs/teleoperation.md): the master and remote sessions of
// config/sessions/teleoperation through the channel model, each row's claim of `hapticd-eval teleoperation` -
// passive and stable with the time-domain passivity approach at every delay and loss, unstable and active without
// it at the long delays - the wall's felt stiffness, the drift, and the same seed giving the same run.
#include <gtest/gtest.h>

#include <cmath>

#include "experiment/teleop_trial.hpp"
#include "support/test_paths.hpp"

namespace hapticd::eval {
namespace {

TeleopResult run(TeleopTask task, teleop::Architecture a, teleop::Passivity p, double rtt_ms, double loss,
                 std::uint64_t seed = 1, bool keep = false) {
  TeleopRow row;
  row.task = task;
  row.round_trip_s = rtt_ms * 1e-3;
  row.loss = loss;
  row.link.architecture = a;
  row.link.passivity = p;
  row.seed = seed;
  row.keep_samples = keep;
  return run_teleop_trial(row, test::source_dir() + "/config/sessions/teleoperation", {test::plugin_dir()});
}

std::string describe(const TeleopResult& r) {
  return "fault '" + r.fault + "', min energy " + std::to_string(r.min_energy_j) + " J, oscillation " +
         std::to_string(r.oscillation_mm) + ", felt " + std::to_string(r.felt_stiffness_n_per_m) + " N/m, drift " +
         std::to_string(r.drift_mm) + " mm";
}

using teleop::Architecture;
using teleop::Passivity;

class Rows : public ::testing::TestWithParam<Architecture> {};

TEST_P(Rows, WithPassivityControlEveryDelayAndLossIsPassiveAndStable) {
  for (const TeleopTask task : {TeleopTask::wall, TeleopTask::free}) {
    for (const double rtt : {0.0, 50.0, 200.0, 500.0}) {
      for (const double loss : {0.0, 0.2}) {
        const TeleopResult r = run(task, GetParam(), Passivity::tdpa, rtt, loss);
        SCOPED_TRACE(std::string(to_string(task)) + " " + std::to_string(rtt) + " ms " + std::to_string(loss));
        EXPECT_TRUE(r.passive) << describe(r);
        EXPECT_TRUE(r.stable) << describe(r);
        EXPECT_GE(r.min_energy_j, -1e-9) << describe(r);  // the controllers' guarantee, up to rounding
        if (task == TeleopTask::free) {
          EXPECT_LT(std::abs(r.drift_mm), 2.0) << describe(r);
        }
        if (task == TeleopTask::wall && rtt == 0.0) {
          EXPECT_GT(r.felt_stiffness_n_per_m, 800.0) << describe(r);
        }
      }
    }
  }
}

TEST_P(Rows, WithoutItTheLongDelaysGoUnstableAndCreateEnergy) {
  for (const double rtt : {200.0, 500.0}) {
    const TeleopResult r = run(TeleopTask::wall, GetParam(), Passivity::none, rtt, 0.05);
    SCOPED_TRACE(std::to_string(rtt) + " ms");
    EXPECT_FALSE(r.stable) << describe(r);
    EXPECT_FALSE(r.passive) << describe(r);
    EXPECT_LT(r.min_energy_j, -1.0) << describe(r);
  }
  // Without delay the same link is stable, and the wall is felt through the remote's controller in series:
  // 5000 N/m and 1500 N/m make 1154 N/m.
  const TeleopResult r = run(TeleopTask::wall, GetParam(), Passivity::none, 0.0, 0.0);
  EXPECT_TRUE(r.stable) << describe(r);
  EXPECT_NEAR(r.felt_stiffness_n_per_m, 1154.0, 120.0) << describe(r);
}

INSTANTIATE_TEST_SUITE_P(Teleoperation, Rows,
                         ::testing::Values(Architecture::position_force, Architecture::position_position),
                         [](const ::testing::TestParamInfo<Architecture>& p) {
                           return std::string(teleop::to_string(p.param));
                         });

TEST(Teleoperation, PositionPositionWithoutPassivityControlIsUnstableInFreeMotionToo) {
  const TeleopResult r = run(TeleopTask::free, Architecture::position_position, Passivity::none, 200.0, 0.0);
  EXPECT_FALSE(r.stable) << describe(r);
  EXPECT_FALSE(r.passive) << describe(r);
}

TEST(Teleoperation, WaveVariablesArePassiveAtEveryDelay) {
  for (const double rtt : {0.0, 200.0, 500.0}) {
    const TeleopResult r = run(TeleopTask::wall, Architecture::position_force, Passivity::wave, rtt, 0.05);
    EXPECT_TRUE(r.passive) << rtt << " ms: " << describe(r);
    EXPECT_TRUE(r.fault.empty()) << describe(r);
  }
}

TEST(Teleoperation, TheSameSeedGivesTheSameRun) {
  const auto a = run(TeleopTask::wall, Architecture::position_force, Passivity::tdpa, 50.0, 0.05, 11, true);
  const auto b = run(TeleopTask::wall, Architecture::position_force, Passivity::tdpa, 50.0, 0.05, 11, true);
  const auto c = run(TeleopTask::wall, Architecture::position_force, Passivity::tdpa, 50.0, 0.05, 12, true);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  ASSERT_FALSE(a.samples.empty());
  for (std::size_t i = 0; i < a.samples.size(); ++i) {
    ASSERT_EQ(a.samples[i].master, b.samples[i].master) << i;
    ASSERT_EQ(a.samples[i].remote_force, b.samples[i].remote_force) << i;
    ASSERT_EQ(a.samples[i].energy, b.samples[i].energy) << i;
  }
  EXPECT_EQ(a.to_remote.lost, b.to_remote.lost);
  EXPECT_NE(a.to_remote.lost, c.to_remote.lost);
  bool differs = false;
  for (std::size_t i = 0; i < std::min(a.samples.size(), c.samples.size()); ++i)
    differs = differs || a.samples[i].master != c.samples[i].master;
  EXPECT_TRUE(differs);
}

// Each side measures the one-way delays and the other's clock from the packets' times alone (the remote's clock
// 12.5 s ahead and 40 ppm fast in every trial): within a millisecond of the channel's truth, through 20 % loss,
// jitter that reorders packets, and no delay at all.
TEST(Teleoperation, BothSidesMeasureTheOneWayDelaysAndTheClockOffset) {
  struct Case {
    double rtt_ms, loss, jitter_ms;
  };
  for (const Case c : {Case{0.0, 0.0, 0.0}, Case{200.0, 0.2, 0.0}, Case{200.0, 0.05, 10.0}, Case{800.0, 0.2, 5.0}}) {
    TeleopRow row;
    row.task = TeleopTask::free;
    row.round_trip_s = c.rtt_ms * 1e-3;
    row.loss = c.loss;
    row.jitter_s = c.jitter_ms * 1e-3;
    row.link.passivity = Passivity::tdpa;
    const TeleopResult r =
        run_teleop_trial(row, test::source_dir() + "/config/sessions/teleoperation", {test::plugin_dir()});
    const TeleopResult::Delays& d = r.delays;
    SCOPED_TRACE(
        std::to_string(c.rtt_ms) + " ms, loss " + std::to_string(c.loss) + ", jitter " + std::to_string(c.jitter_ms) +
        " ms: true " + std::to_string(1e3 * d.true_to_remote_s) + " / " + std::to_string(1e3 * d.true_to_master_s) +
        " ms, the master measured " + std::to_string(1e3 * d.master.mean_delay_out_s) + " / " +
        std::to_string(1e3 * d.master.mean_delay_in_s) + ", the remote " +
        std::to_string(1e3 * d.remote.mean_delay_in_s) + " / " + std::to_string(1e3 * d.remote.mean_delay_out_s));
    ASSERT_TRUE(d.master.valid && d.remote.valid);
    EXPECT_GT(d.master.samples, 4000u);
    EXPECT_EQ(d.master.refused + d.remote.refused, 0u);
    // The truth includes up to one cycle (1 ms) of waiting for the cycle that takes a packet.
    EXPECT_NEAR(d.true_to_remote_s, c.rtt_ms * 0.5e-3 + c.jitter_ms * 0.5e-3, 1.5e-3);
    EXPECT_LT(d.largest_error_s, 1e-3);
    EXPECT_NEAR(d.master.offset_s, d.true_offset_s, 1e-3);
    EXPECT_NEAR(d.remote.offset_s, -d.true_offset_s, 1e-3);
  }
}

// The docs' recommendation, held over a dense sweep rather than the grid's rows (docs/teleoperation.md, "The
// sweep"): position-position with the time-domain controllers holds the wall passive and stable at every round trip
// from 0 to 800 ms in steps of 10 ms, without loss and with 20 %, and keeps at least half its no-delay stiffness.
TEST(Teleoperation, PositionPositionHoldsTheWallAtEveryRoundTripOfTheSweep) {
  double no_delay = 0.0;
  for (const double loss : {0.0, 0.2}) {
    for (int rtt = 0; rtt <= 800; rtt += 10) {
      const TeleopResult r =
          run(TeleopTask::wall, Architecture::position_position, Passivity::tdpa, static_cast<double>(rtt), loss);
      SCOPED_TRACE(std::to_string(rtt) + " ms, loss " + std::to_string(loss));
      EXPECT_TRUE(r.passive && r.stable) << describe(r);
      if (rtt == 0 && loss == 0.0) no_delay = r.felt_stiffness_n_per_m;
      EXPECT_GT(r.felt_stiffness_n_per_m, 0.5 * no_delay) << describe(r);
    }
  }
}

// The evaluation runs the server's port with its policies: a link cut for longer than its timeout stops the remote
// (its E-stop, as the server's link does) and the trial ends there; a shorter cut only fades the master's force.
TEST(Teleoperation, ACutLinkStopsTheRemoteAsTheServersLinkDoes) {
  TeleopRow row;
  row.task = TeleopTask::free;
  row.round_trip_s = 0.05;
  row.link.passivity = Passivity::tdpa;
  row.outage_start_s = 2.0;
  row.outage_s = 1.5;  // the link's timeout: 1 s
  const std::string config = test::source_dir() + "/config/sessions/teleoperation";
  TeleopResult r = run_teleop_trial(row, config, {test::plugin_dir()});
  EXPECT_EQ(r.stop_code, "teleoperation_link_lost");
  EXPECT_EQ(r.fault.rfind("remote: ", 0), 0u) << r.fault;
  row.outage_s = 0.5;
  r = run_teleop_trial(row, config, {test::plugin_dir()});
  EXPECT_EQ(r.stop_code, "");
  EXPECT_EQ(r.fault, "");
  EXPECT_TRUE(r.passive && r.stable) << describe(r);
}

// Six degrees of freedom (docs/teleoperation.md, "Rotation"): the ViSHaRD6 pair (master6.yaml, remote6.yaml), the
// operator pushing the handle into the remote's wall and turning it 0.15 rad, which tilts the remote's plate against
// the wall: position-position with the time-domain controllers holds the contact passive and stable in translation
// and rotation at every round trip from 0 to 800 ms every 10 ms with 20 % loss, and keeps at least half of both
// no-delay stiffnesses; in free motion the remote turns with the master.
TEST(Teleoperation, SixDegreesOfFreedomHoldTheTiltedContactAtEveryRoundTripOfTheSweep) {
  TeleopRow row;
  row.six_dof = true;
  row.link = pair_link(true);
  row.link.architecture = Architecture::position_position;
  const std::string config = test::source_dir() + "/config/sessions/teleoperation";
  const TeleopResult no_delay = run_teleop_trial(row, config, {test::plugin_dir()});
  ASSERT_TRUE(no_delay.passive && no_delay.stable) << describe(no_delay);
  EXPECT_GT(no_delay.felt_rotational_stiffness_n_m_per_rad, 1.0);  // the plate's 4.5 N m/rad in series with the 3
  EXPECT_GT(no_delay.max_torque_n_m, 0.1);
  row.loss = 0.2;
  for (int rtt = 0; rtt <= 800; rtt += 10) {
    row.round_trip_s = rtt * 1e-3;
    const TeleopResult r = run_teleop_trial(row, config, {test::plugin_dir()});
    SCOPED_TRACE(std::to_string(rtt) + " ms, 20 % loss");
    EXPECT_TRUE(r.passive && r.stable) << describe(r) << ", rotation " << r.rotation_oscillation;
    EXPECT_GT(r.felt_stiffness_n_per_m, 0.5 * no_delay.felt_stiffness_n_per_m) << describe(r);
    EXPECT_GT(r.felt_rotational_stiffness_n_m_per_rad, 0.5 * no_delay.felt_rotational_stiffness_n_m_per_rad);
  }
  row.task = TeleopTask::free;
  row.round_trip_s = 0.2;
  const TeleopResult free = run_teleop_trial(row, config, {test::plugin_dir()});
  EXPECT_TRUE(free.passive && free.stable) << describe(free);
  EXPECT_NEAR(free.rotation_oscillation, 1.0, 0.2);  // the remote's rotation over the master's
  // A six-degree-of-freedom row needs the link's rotation.
  row.link.rotation = false;
  EXPECT_THROW(run_teleop_trial(row, config, {test::plugin_dir()}), std::invalid_argument);
}

TEST(Teleoperation, RefusesABadRow) {
  TeleopRow row;
  row.link.stiffness = -5.0;
  EXPECT_THROW(run_teleop_trial(row, test::source_dir() + "/config/sessions/teleoperation", {test::plugin_dir()}),
               std::invalid_argument);
  row = TeleopRow{};
  row.loss = 1.5;
  EXPECT_THROW(run_teleop_trial(row, test::source_dir() + "/config/sessions/teleoperation", {test::plugin_dir()}),
               std::invalid_argument);
}

}  // namespace
}  // namespace hapticd::eval
