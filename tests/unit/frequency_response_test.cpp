// The dynamic force precision analysis (eval/analysis/frequency_response) on synthetic signals with known
// answers: a sinusoid with an offset, noise-free harmonics and a phase; the distortion of a known harmonic; the
// -3 dB bandwidth of a first-order low-pass and the resonance of a second-order system, from their exact
// responses.
#include "frequency_response.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

namespace hapticd::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRate = 2000.0;

std::vector<double> times(double frequency_hz, int periods) {
  std::vector<double> t(static_cast<std::size_t>(std::llround(periods / frequency_hz * kRate)));
  for (std::size_t k = 0; k < t.size(); ++k) t[k] = static_cast<double>(k) / kRate;
  return t;
}

TEST(FrequencyResponse, FitsTheSinusoidAtTheExcitationFrequency) {
  const double f = 7.0;
  const auto t = times(f, 10);
  std::vector<double> y;
  for (double s : t) y.push_back(0.3 + 5.0 * std::sin(2 * kPi * f * s + 0.7));
  const SineFit fit = fit_sine(t, y, f);
  EXPECT_NEAR(fit.amplitude, 5.0, 1e-9);
  EXPECT_NEAR(fit.phase_rad, 0.7, 1e-9);
  EXPECT_NEAR(fit.offset, 0.3, 1e-9);
  EXPECT_NEAR(fit.distortion_percent, 0.0, 1e-7);
}

TEST(FrequencyResponse, TheDistortionIsTheRestOverTheFit) {
  // 5 N at f plus 0.5 N at 3 f over whole periods: the fit takes the first, the rest is the harmonic;
  // D_rms = 100 * rms(0.5 sin) / rms(5 sin) = 10 %.
  const double f = 4.0;
  const auto t = times(f, 8);
  std::vector<double> y;
  for (double s : t) y.push_back(5.0 * std::sin(2 * kPi * f * s) + 0.5 * std::sin(2 * kPi * 3 * f * s));
  const SineFit fit = fit_sine(t, y, f);
  EXPECT_NEAR(fit.amplitude, 5.0, 1e-9);
  EXPECT_NEAR(fit.distortion_percent, 10.0, 1e-6);
}

TEST(FrequencyResponse, GainAndPhaseOfAnOutputAgainstItsInput) {
  const double f = 12.0;
  const auto t = times(f, 6);
  std::vector<double> in, out;
  for (double s : t) {
    in.push_back(5.0 * std::sin(2 * kPi * f * s + 0.2));
    out.push_back(3.5 * std::sin(2 * kPi * f * s + 0.2 - 2.9));  // lags by 2.9 rad
  }
  const FrequencyPoint p = response_at(t, in, out, f);
  EXPECT_NEAR(p.gain, 0.7, 1e-9);
  EXPECT_NEAR(p.phase_rad, -2.9, 1e-9);
  // A lag past -pi comes back wrapped into (-pi, pi].
  for (std::size_t k = 0; k < t.size(); ++k) out[k] = 3.5 * std::sin(2 * kPi * f * t[k] + 0.2 - 3.5);
  EXPECT_NEAR(response_at(t, in, out, f).phase_rad, 2 * kPi - 3.5, 1e-9);
}

TEST(FrequencyResponse, BandwidthOfAFirstOrderLowPassAndResonanceOfASecondOrderSystem) {
  // First order, corner 20 Hz: |G| = 1 / sqrt(1 + (f / 20)^2); points 1..60 Hz every Hz.
  std::vector<FrequencyPoint> first, second;
  const double fn = 30.0, zeta = 0.1;  // second order: peak at fn sqrt(1 - 2 zeta^2) = 29.70 Hz
  for (int k = 1; k <= 60; ++k) {
    const double f = k;
    first.push_back({f, 1.0 / std::sqrt(1.0 + (f / 20.0) * (f / 20.0)), 0.0, 0.0});
    const std::complex<double> s(0.0, f / fn);
    second.push_back({f, std::abs(1.0 / (1.0 + 2.0 * zeta * s + s * s)), 0.0, 0.0});
  }
  const auto bandwidth = bandwidth_3db(first);
  ASSERT_TRUE(bandwidth.has_value());
  // Relative to the 1 Hz point's gain 1 / sqrt(1 + 1/400): 1 + (f/20)^2 = 2 (1 + 1/400), f = 20.05 Hz (linear
  // interpolation in dB between 20 and 21 Hz is good to a few mHz).
  EXPECT_NEAR(*bandwidth, 20.0 * std::sqrt(1.0 + 2.0 / 400.0), 0.01);
  EXPECT_FALSE(resonance_hz(first).has_value());  // no peak
  const auto resonance = resonance_hz(second);
  ASSERT_TRUE(resonance.has_value());
  EXPECT_NEAR(*resonance, 30.0, 0.5);  // the 1 Hz grid's point nearest 29.70 Hz
  // Past the peak the gain falls through -3 dB of the low-frequency gain above fn.
  const auto second_bandwidth = bandwidth_3db(second);
  ASSERT_TRUE(second_bandwidth.has_value());
  EXPECT_GT(*second_bandwidth, fn);
  EXPECT_LT(*second_bandwidth, 1.6 * fn);
  // A response that never falls has no bandwidth.
  EXPECT_FALSE(bandwidth_3db(std::vector<FrequencyPoint>{{1, 1, 0, 0}, {2, 1.1, 0, 0}}).has_value());
}

TEST(FrequencyResponse, RefusesWhatCannotBeFitted) {
  const std::vector<double> t = {0.0, 0.5, 1.0}, y = {0.0, 0.0, 0.0};
  EXPECT_THROW((void)fit_sine(t, y, 1.0), std::invalid_argument);  // every sample at the same phase of 1 Hz
  EXPECT_THROW((void)fit_sine(t, std::vector<double>{1.0, 2.0}, 1.0), std::invalid_argument);
  EXPECT_THROW((void)fit_sine(t, y, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace hapticd::eval
