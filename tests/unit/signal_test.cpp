// The RT signal utilities: Butterworth low-pass and notch sections, the differentiator, the rate limiter.
#include <gtest/gtest.h>

#include <cmath>

#include "hapticd/joint_vector.hpp"
#include "hapticd/signal/biquad.hpp"
#include "hapticd/signal/differentiator.hpp"
#include "hapticd/testing/allocation_guard.hpp"

namespace hapticd {
namespace {

using signal::Biquad;
using signal::BiquadCoefficients;
using Scalar = Eigen::Matrix<double, 1, 1>;

constexpr double kRate = 2000.0;

// Steady-state amplitude of the filter's response to a unit sine at f, by simulation.
double simulated_gain(const BiquadCoefficients& c, double f) {
  Biquad<Scalar> filter(c);
  filter.reset(Scalar::Zero());
  double peak = 0.0;
  const int n = static_cast<int>(kRate * 4.0);
  for (int k = 0; k < n; ++k) {
    const double y = filter.update(Scalar(std::sin(2 * M_PI * f * k / kRate)))[0];
    if (k > n / 2) peak = std::max(peak, std::abs(y));
  }
  return peak;
}

TEST(Biquad, ButterworthLowPassHasUnityDcAndMinus3dBAtCutoff) {
  const auto c = BiquadCoefficients::lowpass(100.0, kRate);
  EXPECT_NEAR(c.gain(0.0, kRate), 1.0, 1e-12);
  EXPECT_NEAR(c.gain(100.0, kRate), 1.0 / std::sqrt(2.0), 1e-9);
  EXPECT_LT(c.gain(800.0, kRate), 0.03);
  EXPECT_NEAR(simulated_gain(c, 100.0), 1.0 / std::sqrt(2.0), 5e-3);
}

TEST(Biquad, NotchRemovesItsFrequencyAndPassesOthers) {
  const auto c = BiquadCoefficients::notch(35.0, 2.0, kRate);
  EXPECT_LT(c.gain(35.0, kRate), 1e-9);
  EXPECT_GT(c.gain(3.5, kRate), 0.99);
  EXPECT_GT(c.gain(350.0, kRate), 0.99);
  EXPECT_LT(simulated_gain(c, 35.0), 0.01);
  EXPECT_NEAR(simulated_gain(c, 2.0), 1.0, 0.01);
}

TEST(Biquad, AnalogNotchHasTheDepthOfItsDampingRatios) {
  // The thesis's torque notch: depth zn / zd = 0.05 at w0, unity far away.
  const auto c = BiquadCoefficients::analog_notch(29.0, 0.01, 0.2, kRate);
  EXPECT_NEAR(c.gain(29.0, kRate), 0.05, 1e-9);
  EXPECT_NEAR(c.gain(0.0, kRate), 1.0, 1e-12);
  EXPECT_GT(c.gain(2.9, kRate), 0.98);
  EXPECT_GT(c.gain(290.0, kRate), 0.98);
  EXPECT_NEAR(simulated_gain(c, 29.0), 0.05, 5e-3);
}

TEST(Biquad, ResetStartsInTheSteadyState) {
  Biquad<JointVector> filter(BiquadCoefficients::lowpass(50.0, kRate));
  JointVector x(3);
  x << 1.0, -2.0, 0.5;
  filter.reset(x);
  for (int k = 0; k < 10; ++k) {
    const JointVector y = filter.update(x);
    ASSERT_LE((y - x).norm(), 1e-12);
  }
}

TEST(Biquad, BadDesignIsRejected) {
  EXPECT_THROW((void)BiquadCoefficients::lowpass(1500.0, kRate), std::invalid_argument);
  EXPECT_THROW((void)BiquadCoefficients::notch(0.0, 1.0, kRate), std::invalid_argument);
  EXPECT_THROW((void)BiquadCoefficients::notch(30.0, 0.0, kRate), std::invalid_argument);
}

TEST(Differentiator, RecoversTheSlopeOfARampAndTheAmplitudeOfASlowSine) {
  signal::Differentiator<Scalar> d;
  d.configure(1.0 / kRate, 200.0);
  d.reset(Scalar::Zero());
  for (int k = 1; k <= 200; ++k) d.update(Scalar(0.3 * k / kRate));
  EXPECT_NEAR(d.value()[0], 0.3, 1e-9);
  d.reset(Scalar::Zero());
  double peak = 0.0;
  for (int k = 1; k <= 4000; ++k) {
    d.update(Scalar(std::sin(2 * M_PI * 1.0 * k / kRate)));
    if (k > 2000) peak = std::max(peak, std::abs(d.value()[0]));
  }
  EXPECT_NEAR(peak, 2 * M_PI, 0.01 * 2 * M_PI);
}

TEST(Differentiator, ASampleAfterSkippedPeriodsIsNotAFastMotion) {
  // A ramp at 0.3 per second sampled every period, then once after 10 periods (a loop that skipped nine):
  // with the elapsed time the slope stays 0.3; divided by one period it would read 3.0.
  signal::Differentiator<Scalar> d;
  d.configure(1.0 / kRate, 200.0);
  d.reset(Scalar::Zero());
  int k = 0;
  for (; k < 200; ++k) d.update(Scalar(0.3 * (k + 1) / kRate));
  k += 10;
  d.update(Scalar(0.3 * k / kRate), 10.0 / kRate);
  EXPECT_NEAR(d.value()[0], 0.3, 1e-9);
}

TEST(RateLimiter, FollowsWithBoundedSlope) {
  signal::RateLimiter<JointVector> r;
  r.configure(1.0 / kRate, 10.0);  // 10 per second: 0.005 per sample
  r.reset(JointVector::Zero(2));
  JointVector target(2);
  target << 1.0, -0.001;
  const JointVector first = r.update(target);
  EXPECT_DOUBLE_EQ(first[0], 0.005);
  EXPECT_DOUBLE_EQ(first[1], -0.001);
  for (int k = 0; k < 300; ++k) r.update(target);
  EXPECT_DOUBLE_EQ(r.value()[0], 1.0);
}

TEST(SignalUtilities, UpdatesDoNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting is off under sanitizers";
  Biquad<JointVector> filter(BiquadCoefficients::notch(30.0, 2.0, kRate));
  signal::Differentiator<JointVector> d;
  signal::RateLimiter<JointVector> r;
  const JointVector x = JointVector::Constant(10, 0.5);
  filter.reset(x);
  d.configure(1.0 / kRate, 100.0);
  d.reset(x);
  r.configure(1.0 / kRate, 1.0);
  r.reset(x);
  double sink = 0.0;
  const std::size_t allocations = testing::count_allocations([&] {
    for (int k = 0; k < 100; ++k) sink += filter.update(x)[0] + d.update(x)[0] + r.update(x)[0];
  });
  EXPECT_EQ(allocations, 0u);
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
}  // namespace hapticd
