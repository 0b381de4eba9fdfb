// The simulated devices' multirate integrator (the rigid-body terms every few substeps, the drive springs,
// motors and friction every substep: FlexibleChain::set_rigid_body_every, the sim plugin's rigid_body_hz)
// against the single-rate one: energy conservation without losses, the drive resonance with the links free,
// and whole devices with every effect on, driven by a joint PD loop while the simulated operator moves the
// handle, in lockstep. The figures are printed and recorded; docs/simulated-devices.md keeps them.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/flexible_chain_rig.hpp"
#include "support/sim_device_fixture.hpp"

namespace hapticd {
namespace {

using sim::FlexibleChain;
using sim::PhysicsOptions;

using test::lossless;

constexpr double kDt = test::kSubstepS;
constexpr int kEvery = 5;  // the default: 4 kHz rigid-body terms at 20 kHz substeps

FlexibleChain make_chain(const char* device, const PhysicsOptions& options, int every) {
  return test::make_chain(device, options, 1, every);
}

class Multirate : public ::testing::TestWithParam<const char*> {};

TEST_P(Multirate, ConservesEnergyAsWellAsTheSingleRateIntegrator) {
  // 1 s of the arm falling and swinging under gravity, lossless: the energy error against the largest kinetic
  // energy, for the single-rate and the multirate integrator.
  double relative[2] = {0.0, 0.0};
  for (int k = 0; k < 2; ++k) {
    FlexibleChain chain = make_chain(GetParam(), lossless(), k == 0 ? 1 : kEvery);
    std::mt19937_64 rng(4);
    chain.reset(test::random_joint_vector(rng, chain.dof(), 1.0));
    const JointVector zero = JointVector::Zero(chain.dof());
    const double e0 = chain.energy();
    double worst = 0.0, largest_kinetic = 0.0;
    for (int step = 0; step < 20000; ++step) {
      chain.step(kDt, zero, model::Vector6d::Zero());
      if (step % 100 == 0) {
        worst = std::max(worst, std::abs(chain.energy() - e0));
        const JointVector& qd = chain.link_velocity();
        largest_kinetic = std::max(largest_kinetic, 0.5 * qd.dot(chain.data().mass_matrix * qd));
      }
    }
    ASSERT_GT(largest_kinetic, 0.1) << "the chain should move";
    relative[k] = worst / largest_kinetic;
  }
  std::printf("%s lossless, 1 s: energy error / largest kinetic energy %.1e single-rate, %.1e multirate\n", GetParam(),
              relative[0], relative[1]);
  RecordProperty("energy_error_single_rate", std::to_string(relative[0]));
  RecordProperty("energy_error_multirate", std::to_string(relative[1]));
  EXPECT_LT(relative[1], 1e-3);  // the single-rate integrator's bound (sim_physics_test)
}

// The drive spring's oscillation with the links free: a torque step on joint `joint`'s motor while the other
// motors are held stiffly; the frequency from the zero crossings of the spring torque's deviation from its
// running mean over the last 5 ms (the links drift under the step).
double free_link_resonance_hz(const char* device, int joint, int every) {
  FlexibleChain chain = make_chain(device, lossless(), every);
  chain.reset(JointVector::Zero(chain.dof()));
  const JointVector rest = chain.motor_position(), feedforward = chain.spring_torque();
  JointVector torque = JointVector::Zero(chain.dof());
  double previous = 0.0, first = -1.0, last = -1.0, mean = feedforward[joint];
  int crossings = 0;
  for (int step = 0; step < 4000; ++step) {  // 0.2 s
    for (int j = 0; j < chain.dof(); ++j)
      torque[j] = j == joint ? feedforward[j] + 2.0
                             : feedforward[j] + 3000.0 * (rest[j] - chain.motor_position()[j]) -
                                   60.0 * chain.motor_velocity()[j];
    chain.step(kDt, torque, model::Vector6d::Zero());
    const double spring = chain.spring_torque()[joint];
    mean += (spring - mean) * kDt / 0.005;
    const double deviation = spring - mean;
    if (step > 200 && (previous < 0.0) != (deviation < 0.0)) {
      if (first < 0) first = step * kDt;
      last = step * kDt;
      ++crossings;
    }
    previous = deviation;
  }
  return crossings > 2 ? (crossings - 1) / 2.0 / (last - first) : 0.0;
}

TEST_P(Multirate, KeepsTheDriveResonanceWithTheLinksFree) {
  const double single = free_link_resonance_hz(GetParam(), 0, 1);
  const double multi = free_link_resonance_hz(GetParam(), 0, kEvery);
  std::printf("%s joint 1, links free: drive resonance %.2f Hz single-rate, %.2f Hz multirate\n", GetParam(), single,
              multi);
  ASSERT_GT(single, 10.0);
  EXPECT_NEAR(multi, single, 0.01 * single);
}

// A whole simulated device with every effect on (friction with stiction, ripple, current loop, structural
// compliance, sensor), the simulated operator moving the handle, a joint PD loop holding the start: the handle
// path and the measured wrench of the single-rate and the multirate integrator side by side.
struct Recording {
  std::vector<Eigen::Vector3d> handle;
  std::vector<double> force;
};

Recording run_device(const std::string& yaml, int rigid_body_hz) {
  test::SimRig rig(yaml + "rigid_body_hz: " + std::to_string(rigid_body_hz) +
                   "\nattachment: operator\noperator_motion: sine\noperator_motion_m: [0.03, 0.02, 0.01]\n");
  const int n = rig.device.description().dof();
  (void)rig.cycle();
  const JointVector start = rig.state.joints.position;
  Recording out;
  for (int k = 0; k < 4000; ++k) {  // 2 s
    rig.command.torque_nm = 150.0 * (start - rig.state.joints.position) - 3.0 * rig.state.joints.velocity;
    rig.command.torque_nm = rig.command.torque_nm.cwiseMax(-20.0).cwiseMin(20.0).head(n);
    (void)rig.cycle();
    out.handle.push_back(rig.device.ground_truth().handle_pose.translation());
    out.force.push_back(rig.device.ground_truth().sensor_wrench.head<3>().norm());
  }
  return out;
}

struct Device {
  const char* name;
  const char* yaml;
};

class MultirateDevice : public ::testing::TestWithParam<Device> {};

TEST_P(MultirateDevice, FollowsTheSingleRateIntegrator) {
  const Recording single = run_device(GetParam().yaml, 0), multi = run_device(GetParam().yaml, 4000);
  double travel = 0.0, position = 0.0, force_scale = 0.0, force = 0.0;
  for (std::size_t k = 0; k < single.handle.size(); ++k) {
    travel = std::max(travel, (single.handle[k] - single.handle[0]).norm());
    position = std::max(position, (multi.handle[k] - single.handle[k]).norm());
    force_scale = std::max(force_scale, single.force[k]);
    force = std::max(force, std::abs(multi.force[k] - single.force[k]));
  }
  std::printf(
      "%s, every effect, 2 s: handle travel %.1f mm, largest difference %.2e mm (%.2e %%); measured force up to "
      "%.2f N, largest difference %.2e N (%.2e %%)\n",
      GetParam().name, travel * 1e3, position * 1e3, 100.0 * position / travel, force_scale, force,
      100.0 * force / force_scale);
  RecordProperty("position_difference_relative", std::to_string(position / travel));
  RecordProperty("force_difference_relative", std::to_string(force / force_scale));
  ASSERT_GT(travel, 0.005);
  EXPECT_LT(position, 1e-3 * travel);  // 1e-5 measured
  EXPECT_LT(force, 1e-3 * force_scale);
}

INSTANTIATE_TEST_SUITE_P(Devices, Multirate, ::testing::ValuesIn(test::kDeviceModels));
INSTANTIATE_TEST_SUITE_P(
    Devices, MultirateDevice,
    ::testing::Values(Device{"vishard3",
                             "urdf: ../urdf/vishard3.urdf\ninitial_position: [-0.3, 1.6, 0.0]\n"
                             "passive_gimbal: true\n"},
                      Device{"vishard6",
                             "urdf: ../urdf/vishard6.urdf\n"
                             "initial_position: [-0.5, 1.0, -0.5, 0.3, 0.3, 0.0]\n"},
                      Device{"vishard10",
                             "urdf: ../urdf/vishard10.urdf\n"
                             "initial_position: [0.3, -0.6, 0.6, -0.6, 0.3, 1.0, -2.0, 1.0, 0.8, 0.0]\n"}),
    [](const ::testing::TestParamInfo<Device>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace hapticd
