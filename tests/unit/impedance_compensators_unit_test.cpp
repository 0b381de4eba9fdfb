// The impedance controller's compensators on their own: the variable-structure relay and integrator, and the
// adaptive re-tuning's checks.
#include <gtest/gtest.h>

#include "friction_retuner.hpp"
#include "stiction_compensator.hpp"

namespace hapticd::controllers {
namespace {

JointVector one(double v) {
  JointVector x(1);
  x[0] = v;
  return x;
}

TEST(StictionCompensator, IntegratesAtRestWithinItsLimit) {
  StictionCompensator s;
  s.configure(1, StictionSettings{100.0, 2.0, 0.05, 0.01}, 1e-3);
  JointVector out(1);
  s.update(one(0.0), one(0.7), one(3.0), out);
  EXPECT_NEAR(out[0], 1e-3 * 100.0 * 3.0, 1e-12) << "at rest: integral of Ki J^T e, no sliding compensation";
  for (int k = 0; k < 1000; ++k) s.update(one(0.0), one(0.7), one(3.0), out);
  EXPECT_DOUBLE_EQ(out[0], 2.0) << "integrator limit";
  EXPECT_FALSE(s.moving(0));
}

TEST(StictionCompensator, RelaySwitchesWithHysteresisAndHoldsTheLastCompensation) {
  StictionCompensator s;
  s.configure(1, StictionSettings{100.0, 2.0, 0.05, 0.01}, 1e-3);
  JointVector out(1);
  s.update(one(0.04), one(0.5), one(1.0), out);
  EXPECT_FALSE(s.moving(0)) << "below the moving threshold";
  s.update(one(0.06), one(0.9), one(1.0), out);
  EXPECT_TRUE(s.moving(0));
  EXPECT_DOUBLE_EQ(out[0], 0.9) << "moving: the sliding compensation";
  s.update(one(0.02), one(0.4), one(1.0), out);
  EXPECT_TRUE(s.moving(0)) << "hysteresis: still moving between the thresholds";
  s.update(one(0.005), one(0.1), one(0.0), out);
  EXPECT_FALSE(s.moving(0));
  EXPECT_DOUBLE_EQ(out[0], 0.4) << "at the switch: the last sliding compensation is held, the integrator restarts";
  EXPECT_DOUBLE_EQ(s.integral(0), 0.0);
}

// Bins filled from a curve (optionally scaled) over [v0, v1].
FrictionBinData bins_from(const model::FrictionModel& m, double v0, double v1, double scale = 1.0) {
  FrictionBinData b;
  b.dof = 1;
  b.bin_width = 0.05;
  for (int i = 0; i < kFrictionBins; ++i) {
    const double v = (i + 0.5) * b.bin_width;
    if (v < v0 || v > v1) continue;
    const auto k = static_cast<std::size_t>(i);
    b.count[0][k] = 500.0;
    b.speed_sum[0][k] = 500.0 * v;
    b.sum[0][k] = 500.0 * scale * m.sliding(v);
  }
  return b;
}

const model::FrictionModel kCurve26{{1.183, 1.008, -0.2642, 0.0487, -0.0037}, {0.0, 0.02, 0.0}, 5.0, 0.0};
const model::FrictionModel kCurve36{{1.033, 0.619, -0.1509, 0.0257, -0.0019}, {0.0, 0.02, 0.0}, 5.0, 0.0};

TEST(FrictionRetuning, AcceptsAWellExcitedFitTowardsTheNewCurve) {
  const RetuneResult r = retune_joint(bins_from(kCurve36, 0.05, 1.5), 0, kCurve26, RetuneChecks{});
  ASSERT_TRUE(r.accepted) << r.reason;
  // Within 5 % of the new curve (the ridge pulls a little towards the present one).
  for (double v = 0.1; v <= 1.4; v += 0.1) EXPECT_NEAR(r.model.sliding(v), kCurve36.sliding(v), 0.05) << v;
}

TEST(FrictionRetuning, RejectsPoorExcitation) {
  const RetuneResult r = retune_joint(bins_from(kCurve36, 0.05, 0.2), 0, kCurve26, RetuneChecks{});
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.reason.find("excitation"), std::string::npos) << r.reason;
  EXPECT_EQ(r.model.p, kCurve26.p) << "a rejected fit keeps the present parameters";
}

TEST(FrictionRetuning, RejectsAFitThatWouldOverCompensateAtLowSpeed) {
  // Data with a spike in the lowest bins pulls the fitted curve above the measurements near rest.
  FrictionBinData b = bins_from(kCurve36, 0.05, 1.5);
  b.sum[0][0] = 500.0 * 0.3;  // very low friction measured in the lowest bin
  b.sum[0][1] = 500.0 * 0.35;
  RetuneChecks checks;
  checks.fraction = 1.0;
  const RetuneResult r = retune_joint(b, 0, kCurve26, checks);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.reason.find("over-compensation"), std::string::npos) << r.reason;
}

TEST(FrictionRetuning, RejectsAnImplausibleCurve) {
  FrictionBinData b = bins_from(kCurve36, 0.05, 1.5, -1.0);  // negative friction: nonsense estimates
  const RetuneResult r = retune_joint(b, 0, kCurve26, RetuneChecks{});
  EXPECT_FALSE(r.accepted);
}

}  // namespace
}  // namespace hapticd::controllers
