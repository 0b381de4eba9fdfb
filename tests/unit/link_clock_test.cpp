// The link's delay and the peer's clock from the packets' times (teleop/link_clock.hpp, docs/teleoperation.md,
// "Measured delay"): exact for a symmetric path whatever the clocks' offset; through jitter and a drifting clock
// within a fraction of a millisecond; an asymmetric path read as half the round trip each way (what two clocks
// cannot tell apart); impossible times refused and counted, whatever their size.
#include "hapticd/teleop/link_clock.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace hapticd::teleop {
namespace {

constexpr std::int64_t kMs = 1'000'000;

// Exchanges every millisecond for `seconds`: this side sends at t (own clock), the packet takes `out` to the
// peer, which answers `hold` later (the peer's clock: peer(t) = offset + t * rate); the answer takes `back`.
// Returns the true mean of the one-way delays to this side.
template <class Out, class Back>
double run(LinkClock& clock, double seconds, std::int64_t offset, double rate, Out out, Back back,
           std::int64_t hold = 300'000) {
  auto peer = [&](std::int64_t t) { return offset + std::llround(static_cast<double>(t) * rate); };
  double sum = 0.0;
  int n = 0;
  for (std::int64_t t1 = kMs; t1 < std::llround(seconds * 1e9); t1 += kMs) {
    const std::int64_t arrive = t1 + out();
    const std::int64_t answer = arrive + hold;
    const std::int64_t delay = back();
    clock.exchange(t1, peer(arrive), peer(answer), answer + delay);
    sum += static_cast<double>(delay) * 1e-9;
    ++n;
  }
  return sum / n;
}

TEST(LinkClock, ASymmetricPathAndAnyClockOffsetAreMeasuredExactly) {
  for (const std::int64_t offset : {std::int64_t{0}, 5'000 * kMs, -123'456'789'012'345, std::int64_t{1} << 62}) {
    LinkClock clock;
    run(
        clock, 3.0, offset, 1.0, [] { return 100 * kMs; }, [] { return 100 * kMs; });
    const LinkClockFigures& f = clock.figures();
    SCOPED_TRACE(offset);
    ASSERT_TRUE(f.valid);
    EXPECT_EQ(f.samples, 2999u);
    EXPECT_EQ(f.refused, 0u);
    EXPECT_NEAR(f.round_trip_s, 0.2, 1e-9);
    EXPECT_NEAR(f.offset_s, static_cast<double>(offset) * 1e-9, 1e-9 * std::max(1.0, std::abs(offset * 1e-18)));
    EXPECT_NEAR(f.delay_in_s, 0.1, 1e-6);
    EXPECT_NEAR(f.delay_out_s, 0.1, 1e-6);
    EXPECT_NEAR(f.mean_delay_in_s, 0.1, 1e-6);
  }
}

TEST(LinkClock, JitterAndADriftingClockAreSeenThrough) {
  // 100 ms each way plus up to 20 ms of jitter each, the peer's clock 50 ppm fast: the offset is taken from the
  // least disturbed exchange of the last 2 s, so it follows the drift (0.1 ms in 2 s) and ignores the jitter.
  std::mt19937_64 random(7);
  std::uniform_int_distribution<std::int64_t> jitter(0, 20 * kMs);
  LinkClock clock;
  const double rate = 1.0 + 50e-6;
  const double true_in = run(
      clock, 20.0, 3'000 * kMs, rate, [&] { return 100 * kMs + jitter(random); },
      [&] { return 100 * kMs + jitter(random); });
  const LinkClockFigures& f = clock.figures();
  const double true_offset_now = 3.0 + 20.0 * 50e-6;  // the peer's clock minus this one's at the end
  // The least disturbed of 2 000 exchanges came back within a millisecond of the path's own 200 ms; the offset is
  // off by at most half of that excess (its split between the ways) and the drift within the window.
  EXPECT_GE(f.round_trip_s, 0.2);
  EXPECT_LT(f.round_trip_s, 0.201);
  EXPECT_LE(std::abs(f.offset_s - true_offset_now), (f.round_trip_s - 0.2) / 2.0 + 0.1e-3);
  EXPECT_NEAR(f.mean_delay_in_s, true_in, 0.5e-3);
  EXPECT_NEAR(f.mean_delay_out_s, 0.110, 0.5e-3);
  // The first exchange's offset, taken as it came, would be off by up to 10 ms (half the jitter): the filter is
  // what gives the figures above.
}

// Two servers' loops stamp their packets with their cycles' times: every time is a multiple of 1 ms on its own
// clock, so one exchange's offset is off by up to a cycle (a two-server run read 23 ms for a relay's 21). The mean
// of the exchanges that took the shortest round trip sees through the ticks.
TEST(LinkClock, ClocksThatTickInCyclesAreSeenThroughByTheShortestExchangesMean) {
  std::mt19937_64 random(11);
  std::uniform_int_distribution<std::int64_t> jitter(0, 2 * kMs);
  const std::int64_t offset = 12'500 * kMs + 370'000;  // the peer's clock minus this one's: its cycles 0.37 ms apart
  auto tick_after = [](std::int64_t t) { return (t / kMs + 1) * kMs; };  // the next cycle's time (either clock)
  LinkClock clock;
  double worst = 0.0;
  for (std::int64_t t1 = kMs; t1 < 10'000 * kMs; t1 += kMs) {
    const std::int64_t t2 = tick_after(t1 + 20 * kMs + jitter(random) + offset);  // taken at the peer's next cycle
    const std::int64_t t3 = t2;                                                   // and answered in that cycle
    const std::int64_t t4 = tick_after(t3 - offset + 20 * kMs + jitter(random));
    clock.exchange(t1, t2, t3, t4);
    if (t1 > 2'000 * kMs) worst = std::max(worst, std::abs(clock.figures().offset_s - offset * 1e-9));
  }
  EXPECT_LT(worst, 0.3e-3);
}

TEST(LinkClock, AnAsymmetricPathReadsAsHalfTheRoundTripEachWay) {
  LinkClock clock;
  run(
      clock, 3.0, 7'000 * kMs, 1.0, [] { return 150 * kMs; }, [] { return 50 * kMs; });
  const LinkClockFigures& f = clock.figures();
  EXPECT_NEAR(f.round_trip_s, 0.2, 1e-9);
  EXPECT_NEAR(f.delay_in_s, 0.1, 1e-6);       // truly 50 ms: no pair of clocks can tell
  EXPECT_NEAR(f.delay_out_s, 0.1, 1e-6);      // truly 150 ms
  EXPECT_NEAR(f.offset_s, 7.0 + 0.05, 1e-6);  // off by half the asymmetry
}

TEST(LinkClock, ImpossibleTimesAreRefusedAndCountedWhateverTheirSize) {
  LinkClock clock;
  constexpr std::int64_t lo = std::numeric_limits<std::int64_t>::min(), hi = std::numeric_limits<std::int64_t>::max();
  clock.exchange(10 * kMs, 0, -1, 20 * kMs);  // the peer answered before the packet arrived
  clock.exchange(30 * kMs, 0, 0, 20 * kMs);   // it arrived here before this side sent the echoed one
  clock.exchange(0, 0, 50 * kMs, 20 * kMs);   // the peer held it longer than the round trip
  clock.exchange(lo, hi, lo, hi);             // extremes
  clock.exchange(hi, lo, hi, lo);
  clock.exchange(0, lo, hi, 700'000 * kMs);  // an echo older than any link's round trip
  EXPECT_EQ(clock.figures().refused, 6u);
  EXPECT_EQ(clock.figures().samples, 0u);
  EXPECT_FALSE(clock.figures().valid);
  clock.exchange(0, 5 * kMs, 6 * kMs, 10 * kMs);  // and a sound one is still taken
  EXPECT_TRUE(clock.figures().valid);
  EXPECT_NEAR(clock.figures().round_trip_s, 9e-3, 1e-12);
  clock.reset();
  EXPECT_FALSE(clock.figures().valid);
  EXPECT_EQ(clock.figures().refused, 0u);
}

}  // namespace
}  // namespace hapticd::teleop
