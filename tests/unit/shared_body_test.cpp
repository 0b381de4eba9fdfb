// The shared virtual object of bimanual coupling, on its own (the loop's period, fixed steps): it rests on the
// table carrying its weight; two hands lift it 10 cm and turn it 30 degrees about the vertical, feeling its
// weight between them; a squeeze shows as the internal force it is; a step allocates nothing.
#include "hapticd/model/shared_body.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hapticd/testing/allocation_guard.hpp"

namespace hapticd::model {
namespace {

constexpr double kPeriod = 0.0005;
constexpr double kPi = 3.14159265358979323846;

SharedBodySettings box() {
  SharedBodySettings s;
  s.mass_kg = 1.0;
  s.size_m = Eigen::Vector3d(0.30, 0.15, 0.10);
  return s;
}

Pose at(const Eigen::Vector3d& p) {
  Pose pose;
  pose.position = p;
  return pose;
}

double yaw_of(const Eigen::Quaterniond& q) {
  const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x());
}

// A smooth 0 -> 1 over [start, start + duration] (zero velocity at both ends).
double smooth(double t, double start, double duration) {
  const double s = std::clamp((t - start) / duration, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

TEST(SharedBody, RestsOnTheTableCarryingItsWeight) {
  SharedBody body;
  body.configure(box(), kPeriod);
  body.reset(at({0.1, -0.2, 0.10}), {});  // its bottom 5 cm above the table
  for (int k = 0; k < 4000; ++k) body.step({}, {}, {});
  EXPECT_NEAR(body.table_force().z(), 9.81, 0.01);
  EXPECT_NEAR(body.position().z(), 0.05, 0.001);  // resting, sunk by its weight over four corner springs
  EXPECT_NEAR(body.position().x(), 0.1, 1e-6);
  EXPECT_NEAR(body.position().y(), -0.2, 1e-6);
  EXPECT_LT(body.velocity().norm(), 1e-4);
}

TEST(SharedBody, TwoHandsLiftItTenCentimetresAndTurnItThirtyDegrees) {
  SharedBody body;
  body.configure(box(), kPeriod);
  const Eigen::Vector3d centre(0.0, 0.0, 0.05);
  // Settle on the table first, then attach the hands at the box's ends.
  body.reset(at(centre), {});
  for (int k = 0; k < 2000; ++k) body.step({}, {}, {});
  const Eigen::Vector3d start = body.position();
  const std::vector<Eigen::Vector3d> grasp = {{-0.15, 0.0, 0.0}, {0.15, 0.0, 0.0}};
  Pose settled = at(start);
  body.reset(settled, grasp);
  std::vector<Eigen::Vector3d> hand(2), hand_velocity(2, Eigen::Vector3d::Zero()), force(2);
  double internal_max = 0.0;
  // 0-1 s: both hands up 10 cm; 1.5-2.5 s: both turn 30 degrees about the vertical through the box's centre;
  // then hold until 4 s.
  for (int k = 0; k < 8000; ++k) {
    const double t = k * kPeriod;
    const double lift = 0.10 * smooth(t, 0.0, 1.0);
    const double turn = (30.0 * kPi / 180.0) * smooth(t, 1.5, 1.0);
    const Eigen::Vector3d axis_point = start + Eigen::Vector3d(0, 0, lift);
    for (std::size_t h = 0; h < 2; ++h) {
      const Eigen::Vector3d next = axis_point + Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()) * grasp[h];
      hand_velocity[h] = k == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d((next - hand[h]) / kPeriod);
      hand[h] = next;
    }
    body.step(hand, hand_velocity, force);
    if (t > 0.5) internal_max = std::max(internal_max, std::abs(body.internal_force_n()));
  }
  EXPECT_NEAR(body.position().z() - start.z(), 0.10 - 9.81 / (2 * 2000.0), 0.002);  // lifted, sagging 2.5 mm
  EXPECT_NEAR(yaw_of(body.orientation()) * 180.0 / kPi, 30.0, 0.5);
  EXPECT_NEAR(body.table_force().norm(), 0.0, 1e-9);  // off the table
  // Held still: the hands carry its weight between them, half each, and nothing else.
  EXPECT_NEAR((force[0] + force[1]).z(), -9.81, 0.01);
  EXPECT_NEAR(force[0].z(), -4.905, 0.05);
  EXPECT_NEAR((force[0] + force[1]).head<2>().norm(), 0.0, 0.01);
  // Hands that keep the grasp points' distance squeeze nothing (the internal force of a rigid turn and lift).
  EXPECT_LT(internal_max, 0.5);
  EXPECT_NEAR(body.internal_force_n(), 0.0, 0.05);
}

TEST(SharedBody, ASqueezeIsTheInternalForce) {
  SharedBody body;
  SharedBodySettings s = box();
  s.table = false;
  s.gravity.setZero();
  body.configure(s, kPeriod);
  const std::vector<Eigen::Vector3d> grasp = {{-0.15, 0.0, 0.0}, {0.15, 0.0, 0.0}};
  body.reset(at(Eigen::Vector3d::Zero()), grasp);
  // Each hand 5 mm inside its grasp point: 2000 N/m * 5 mm = 10 N of squeeze, and no net force.
  const std::vector<Eigen::Vector3d> hand = {{-0.145, 0.0, 0.0}, {0.145, 0.0, 0.0}};
  const std::vector<Eigen::Vector3d> still(2, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> force(2);
  for (int k = 0; k < 2000; ++k) body.step(hand, still, force);
  EXPECT_NEAR(body.internal_force_n(), 10.0, 1e-6);
  EXPECT_NEAR(force[0].x(), -10.0, 1e-6);  // each hand is pushed back out
  EXPECT_NEAR(force[1].x(), 10.0, 1e-6);
  EXPECT_LT(body.position().norm(), 1e-9);
  // Pulled apart instead: negative.
  const std::vector<Eigen::Vector3d> apart = {{-0.155, 0.0, 0.0}, {0.155, 0.0, 0.0}};
  for (int k = 0; k < 10; ++k) body.step(apart, still, force);
  EXPECT_NEAR(body.internal_force_n(), -10.0, 1e-6);
}

TEST(SharedBody, AStepDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  SharedBody body;
  body.configure(box(), kPeriod);
  const std::vector<Eigen::Vector3d> grasp = {{-0.15, 0.0, 0.0}, {0.15, 0.0, 0.0}};
  body.reset(at({0.0, 0.0, 0.05}), grasp);
  const std::vector<Eigen::Vector3d> hand = {{-0.15, 0.0, 0.06}, {0.15, 0.0, 0.06}};
  const std::vector<Eigen::Vector3d> still(2, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> force(2);
  testing::AllocationGuard guard;
  for (int k = 0; k < 1000; ++k) body.step(hand, still, force);
  EXPECT_EQ(guard.allocations(), 0u);
}

}  // namespace
}  // namespace hapticd::model
