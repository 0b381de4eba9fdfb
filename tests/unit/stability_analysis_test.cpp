// The stability analyses of hapticd-eval (eval/analysis/stability) against known answers: the
// oscillation measure on a limit cycle, a decaying ring-down and slow voluntary motion; the bisection on a
// known boundary and on a sampled mass-spring-damper whose stability condition is analytic; the passivity of a
// sampled wall against Colgate and Brown's condition b > K T / 2 + |B|, as a Z-width region.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "stability.hpp"

namespace hapticd::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRate = 2000.0;

std::vector<double> sampled(double seconds, const std::function<double(double)>& f) {
  std::vector<double> y(static_cast<std::size_t>(seconds * kRate));
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = f(static_cast<double>(k) / kRate);
  return y;
}

TEST(StabilityAnalysis, TheOscillationMeasureKeepsALimitCycleAndDropsSlowMotion) {
  // An 8 Hz limit cycle of 1 mm on top of a 0.5 Hz, 4 cm voluntary motion: its velocity amplitude is
  // 2 pi 8 1e-3 = 0.0503 m/s, RMS 0.0355 m/s; the motion's (0.126 m/s) is attenuated by about (0.5/4)^2.
  const auto v = sampled(2.0, [](double t) {
    return 0.04 * 2 * kPi * 0.5 * std::cos(2 * kPi * 0.5 * t) + 1e-3 * 2 * kPi * 8 * std::cos(2 * kPi * 8 * t);
  });
  const Oscillation cycle = oscillation(v, kRate, 4.0, 0.5);
  EXPECT_NEAR(cycle.rms, 0.0355, 0.004);
  EXPECT_NEAR(cycle.frequency_hz, 8.0, 0.2);
  const auto motion_only = sampled(2.0, [](double t) { return 0.04 * 2 * kPi * 0.5 * std::cos(2 * kPi * 0.5 * t); });
  EXPECT_LT(oscillation(motion_only, kRate, 4.0, 0.5).rms, 0.003);
  // A ring-down (20 Hz, decay 0.05 s) is gone by the last half second.
  const auto ring = sampled(2.0, [](double t) { return 0.1 * std::exp(-t / 0.05) * std::sin(2 * kPi * 20 * t); });
  EXPECT_LT(oscillation(ring, kRate, 4.0, 0.5).rms, 1e-6);
  // A constant offset is not an oscillation.
  EXPECT_LT(oscillation(std::vector<double>(4000, 0.3), kRate, 4.0, 0.5).rms, 1e-12);
  EXPECT_THROW((void)oscillation(v, kRate, 1000.0, 0.5), std::invalid_argument);
  EXPECT_THROW((void)oscillation(v, kRate, 4.0, 3.0), std::invalid_argument);
}

TEST(StabilityAnalysis, BisectionFindsAKnownBoundary) {
  int calls = 0;
  const Bisection r = smallest_stable([&](double m) { return ++calls, m >= 2.37; }, 0.1, 20.0, 0.02);
  EXPECT_GE(r.value, 2.37);
  EXPECT_LE(r.value, 2.37 * 1.02);
  EXPECT_LT(r.unstable, 2.37);
  EXPECT_LE(r.value / r.unstable, 1.02);
  EXPECT_FALSE(r.below_range);
  EXPECT_FALSE(r.above_range);
  EXPECT_EQ(r.evaluations, calls);
  EXPECT_LE(calls, 12);  // log2(ln(200) / ln(1.02)) + 2

  const Bisection wall = largest_stable([](double k) { return k <= 3000.0; }, 10.0, 1e6, 0.01);
  EXPECT_LE(wall.value, 3000.0);
  EXPECT_GE(wall.value, 3000.0 / 1.01);
  EXPECT_GT(wall.unstable, 3000.0);

  EXPECT_TRUE(smallest_stable([](double) { return true; }, 0.1, 20.0, 0.05).below_range);
  EXPECT_TRUE(smallest_stable([](double) { return false; }, 0.1, 20.0, 0.05).above_range);
  EXPECT_TRUE(largest_stable([](double) { return false; }, 10.0, 1e6, 0.05).below_range);
  EXPECT_TRUE(largest_stable([](double) { return true; }, 10.0, 1e6, 0.05).above_range);
  EXPECT_THROW((void)smallest_stable([](double) { return true; }, 2.0, 1.0, 0.05), std::invalid_argument);
}

// A virtual mass m with a damper b against a spring k, integrated by semi-implicit Euler at period T (the
// virtual admittance's integrator): v+ = v + T (-k x - b v) / m, x+ = x + T v+. By Jury's test it is stable iff
// m > (k T^2 + 2 b T) / 4. The simulated velocity, judged by the oscillation measure, finds that boundary.
TEST(StabilityAnalysis, BisectionWithTheOscillationMeasureFindsAnAnalyticBoundary) {
  const double k = 20000.0, b = 30.0, t = 1.0 / kRate;
  const double boundary = (k * t * t + 2.0 * b * t) / 4.0;  // 0.00875 kg
  const auto stable = [&](double m) {
    std::vector<double> v(static_cast<std::size_t>(2.0 * kRate));
    double x = 1e-3, vel = 0.0;
    for (double& s : v) {
      vel += t * (-k * x - b * vel) / m;
      x += t * vel;
      s = vel;
    }
    return oscillation(v, kRate, 4.0, 0.5).rms < 0.02;
  };
  const Bisection r = smallest_stable(stable, 1e-3, 1.0, 0.01);
  EXPECT_NEAR(r.value, boundary, 0.02 * boundary);
}

TEST(StabilityAnalysis, ASampledWallIsPassiveExactlyWhereColgatesConditionHolds) {
  const SampledWall device{2.0, 1e-3};  // b = 2 N s/m, T = 1 ms
  // Below the boundary K = 2 (b - |B|) / T, above it not: the Z-width region, per virtual damping B.
  for (const double damping : {0.0, 0.5, 1.0, -0.5}) {
    const double boundary = 2.0 * (device.damping_n_s_per_m - std::abs(damping)) / device.period_s;
    const Bisection r = largest_stable(
        [&](double stiffness) { return sampled_wall_passive(device, stiffness, damping); }, 1.0, 1e5, 0.002);
    SCOPED_TRACE(damping);
    EXPECT_NEAR(r.value, boundary, 0.01 * boundary);
  }
  // Energy per period at one frequency: a wall of K = 5000 N/m (KT/2 = 2.5 > b) at 5 Hz gives energy out.
  EXPECT_LT(sampled_wall_energy_per_period(device, 5000.0, 0.0, 5.0), 0.0);
  EXPECT_GT(sampled_wall_energy_per_period(device, 3000.0, 0.0, 5.0), 0.0);
  EXPECT_THROW((void)sampled_wall_energy_per_period(device, 1.0, 0.0, 600.0), std::invalid_argument);
}

}  // namespace
}  // namespace hapticd::eval
