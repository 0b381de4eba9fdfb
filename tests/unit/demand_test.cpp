// HAPTICD_DEMAND (hapticd/demand.hpp): an invariant checked in every build; a broken one prints what and where,
// then aborts. Death tests: each failure runs in a child process.
#include "hapticd/demand.hpp"

#include <gtest/gtest.h>

#include "session/torque_blend.hpp"

namespace hapticd {
namespace {

TEST(Demand, ATrueConditionPassesAndAFalseOneAbortsSayingWhatAndWhere) {
  int evaluated = 0;
  HAPTICD_DEMAND(++evaluated == 1);  // evaluated once
  EXPECT_EQ(evaluated, 1);
  EXPECT_DEATH(HAPTICD_DEMAND(evaluated == 2),
               "internal invariant failed: evaluated == 2 \\(.*demand_test.cpp:[0-9]+\\)");
}

TEST(Demand, ATorqueBlendFromAnotherDevicesJointsIsABug) {
  server::TorqueBlend blend(10);
  blend.begin(JointVector::Zero(2));
  JointVector command = JointVector::Zero(3);
  EXPECT_DEATH(blend.apply(command), "offset_.size\\(\\) == command.size\\(\\)");
}

}  // namespace
}  // namespace hapticd
