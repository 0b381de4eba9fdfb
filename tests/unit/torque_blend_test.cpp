// The torque blend after a scheme switch or a recovery (server/src/session/torque_blend): the difference between
// the torque the drives held and the chain's first command fades out linearly, so the drives see no step.
#include "session/torque_blend.hpp"

#include <gtest/gtest.h>

namespace hapticd::server {
namespace {

JointVector joints(double a, double b) {
  JointVector v(2);
  v << a, b;
  return v;
}

TEST(TorqueBlend, TheHeldTorqueFadesIntoTheChainsCommandsOverTheRamp) {
  TorqueBlend blend(4);
  EXPECT_FALSE(blend.active());
  blend.begin(joints(2.0, -1.0));
  EXPECT_TRUE(blend.active());
  // The chain's commands: 0.0 then 1.0 on the first joint. The first cycle writes exactly what was held.
  JointVector c = joints(0.0, 0.0);
  blend.apply(c);
  EXPECT_DOUBLE_EQ(c[0], 2.0);
  EXPECT_DOUBLE_EQ(c[1], -1.0);
  // Then 3/4, 2/4, 1/4 of the difference (taken against the first command) on top of each new command.
  const double expected_first[] = {1.0 + 2.0 * 0.75, 1.0 + 2.0 * 0.5, 1.0 + 2.0 * 0.25};
  for (double e : expected_first) {
    c = joints(1.0, 0.0);
    blend.apply(c);
    EXPECT_DOUBLE_EQ(c[0], e);
  }
  EXPECT_FALSE(blend.active());
  c = joints(1.0, 0.0);
  blend.apply(c);
  EXPECT_DOUBLE_EQ(c[0], 1.0);  // done: the chain's command unchanged
}

TEST(TorqueBlend, CancelLeavesTheCommandAlone) {
  TorqueBlend blend(10);
  blend.begin(joints(5.0, 5.0));
  blend.cancel();
  JointVector c = joints(1.0, 2.0);
  blend.apply(c);
  EXPECT_DOUBLE_EQ(c[0], 1.0);
  EXPECT_DOUBLE_EQ(c[1], 2.0);
  EXPECT_FALSE(blend.active());
}

TEST(TorqueBlend, ARampShorterThanACycleIsOneCycle) {
  TorqueBlend blend(0);
  blend.begin(joints(3.0, 0.0));
  JointVector c = joints(0.0, 0.0);
  blend.apply(c);
  EXPECT_DOUBLE_EQ(c[0], 3.0);
  EXPECT_FALSE(blend.active());
}

}  // namespace
}  // namespace hapticd::server
