// The simulated environment's wall (plugins/devices/sim/environment_wall.hpp): a point contact pushes along the
// normal, never pulls; a plate contact pushes with the whole spring when flat and turns a tilted handle back - the
// six-degree-of-freedom contact the teleoperation remote holds.
#include "environment_wall.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace hapticd::sim {
namespace {

Eigen::Isometry3d at(const Eigen::Vector3d& p, const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.toRotationMatrix();
  pose.translation() = p;
  return pose;
}

WallSettings wall(double half_width) {
  WallSettings s;
  s.normal = Eigen::Vector3d::UnitX();
  s.offset_m = 0.03;
  s.stiffness = 5000.0;
  s.damping = 0.0;
  s.contact_half_width_m = half_width;
  return s;
}

TEST(EnvironmentWall, APointContactPushesAlongTheNormalAndNeverPulls) {
  EnvironmentWall w;
  w.configure(wall(0.0));
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  EXPECT_EQ(w.wrench(at({0.5, 0, 0}), zero, zero).force.norm(), 0.0);  // placed here: the wall 3 cm ahead
  const WallWrench in = w.wrench(at({0.54, 0.1, 0}), zero, zero);
  EXPECT_NEAR(in.force.x(), -50.0, 1e-9);
  EXPECT_EQ(in.torque.norm(), 0.0);
  WallSettings damped = wall(0.0);
  damped.damping = 1000.0;
  w.configure(damped);
  EXPECT_EQ(w.wrench(at({0.54, 0, 0}), {-1.0, 0, 0}, zero).force.norm(), 0.0);  // leaving fast: no pull
}

TEST(EnvironmentWall, APlatePushesWithTheWholeSpringFlatAndTurnsATiltedHandleBack) {
  EnvironmentWall w;
  w.configure(wall(0.02));
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  (void)w.wrench(at({0.5, 0, 0}), zero, zero);
  const WallWrench flat = w.wrench(at({0.54, 0, 0}), zero, zero);
  EXPECT_NEAR(flat.force.x(), -50.0, 1e-9);
  EXPECT_NEAR(flat.torque.norm(), 0.0, 1e-12);
  // Tilted about z by 0.1 rad: one edge goes deeper, the other less - the wall turns the handle back.
  for (const double angle : {-0.1, -0.02, 0.02, 0.1}) {
    const Eigen::Quaterniond tilt(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
    const WallWrench t = w.wrench(at({0.54, 0, 0}, tilt), zero, zero);
    EXPECT_LT(t.torque.z() * angle, 0.0) << angle;                        // against the tilt
    EXPECT_NEAR(t.torque.x(), 0.0, 1e-9) << angle;                        // nothing about the normal
    EXPECT_NEAR(t.force.x(), -50.0, 0.5 + 2e3 * angle * angle) << angle;  // the same push, near enough
  }
  // Small tilts: the torque per radian is the plate's rotational stiffness, k h^2 (four corners, a quarter each).
  const Eigen::Quaterniond small(Eigen::AngleAxisd(1e-4, Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(-w.wrench(at({0.54, 0, 0}, small), zero, zero).torque.z() / 1e-4, 5000.0 * 0.02 * 0.02, 0.05);
  // Out of contact: nothing, tilted or not.
  EXPECT_EQ(w.wrench(at({0.52, 0, 0}, small), zero, zero).force.norm(), 0.0);
}

}  // namespace
}  // namespace hapticd::sim
