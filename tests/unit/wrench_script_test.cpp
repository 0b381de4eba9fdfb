// The scripted wrench's signals against their definitions: zero before the start, sine, chirp (the phase is the
// integral of the sweeping frequency), steps (each level held, the last kept), and the set-up errors.
#include "wrench_script.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace hapticd::models {
namespace {

WrenchScript make(const WrenchScript::Settings& s) {
  WrenchScript w;
  w.configure(s);
  return w;
}

TEST(WrenchScript, SineStartsAtItsStartWithTheGivenAmplitudeAndFrequency) {
  WrenchScript::Settings s;
  s.signal = WrenchScript::Signal::sine;
  s.direction << 0, 0, 5, 0, 0, 0;
  s.start_s = 0.5;
  s.frequency_hz = 7.0;
  const WrenchScript w = make(s);
  EXPECT_EQ(w.at(0.49).norm(), 0.0);
  for (double t : {0.5, 0.61, 1.234}) {
    EXPECT_NEAR(w.at(t)[2], 5.0 * std::sin(2 * M_PI * 7.0 * (t - 0.5)), 1e-12);
    EXPECT_EQ(w.at(t)[0], 0.0);
  }
  EXPECT_DOUBLE_EQ(w.frequency_at(1.0), 7.0);
}

TEST(WrenchScript, ChirpSweepsLinearlyAndItsZeroCrossingsFollowTheFrequency) {
  WrenchScript::Settings s;
  s.signal = WrenchScript::Signal::chirp;
  s.direction << 1, 0, 0, 0, 0, 0;
  s.chirp_start_hz = 1.0;
  s.chirp_end_hz = 21.0;
  s.chirp_duration_s = 10.0;
  const WrenchScript w = make(s);
  EXPECT_DOUBLE_EQ(w.frequency_at(5.0), 11.0);
  // Half-periods counted from zero crossings around t = 5 s match 1 / (2 f(t)).
  double previous = w.signal(4.9);
  std::vector<double> crossings;
  for (double t = 4.9; t < 5.1; t += 1e-6) {
    const double v = w.signal(t);
    if ((previous < 0.0) != (v < 0.0)) crossings.push_back(t);
    previous = v;
  }
  ASSERT_GE(crossings.size(), 3u);
  const double half_period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  EXPECT_NEAR(half_period, 1.0 / (2.0 * 11.0), 1e-3);
  EXPECT_EQ(w.signal(10.01), 0.0) << "zero after the sweep";
}

TEST(WrenchScript, StepsHoldEachLevelAndKeepTheLast) {
  WrenchScript::Settings s;
  s.signal = WrenchScript::Signal::steps;
  s.direction << 0, 2, 0, 0, 0, 1;
  s.levels = {1.0, -0.5, 0.25};
  s.step_s = 0.2;
  const WrenchScript w = make(s);
  EXPECT_DOUBLE_EQ(w.at(0.1)[1], 2.0);
  EXPECT_DOUBLE_EQ(w.at(0.3)[1], -1.0);
  EXPECT_DOUBLE_EQ(w.at(0.3)[5], -0.5);
  EXPECT_DOUBLE_EQ(w.at(0.5)[1], 0.5);
  EXPECT_DOUBLE_EQ(w.at(100.0)[1], 0.5);
}

TEST(WrenchScript, RefusesWhatItCannotPlay) {
  WrenchScript::Settings s;
  s.signal = WrenchScript::Signal::steps;
  EXPECT_THROW(make(s), std::invalid_argument) << "steps without levels";
  s.levels.assign(33, 1.0);
  EXPECT_THROW(make(s), std::invalid_argument) << "more levels than the fixed storage";
  s.signal = WrenchScript::Signal::chirp;
  s.chirp_duration_s = 0.0;
  EXPECT_THROW(make(s), std::invalid_argument);
  EXPECT_THROW(WrenchScript::parse("square"), std::invalid_argument);
}

}  // namespace
}  // namespace hapticd::models
