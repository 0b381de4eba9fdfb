// The gate's round-trip probe (server/src/gate/round_trip_probe): state written -> command handed to the
// loop, and how many cycles after the state's the loop applied the command; slots reused by newer states are
// never mistaken for the old ones, and the hand-off between the publisher and the receive thread is consistent.
#include "gate/round_trip_probe.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace hapticd::server {
namespace {

TEST(RoundTripProbe, MeasuresFromTheStateWrittenToTheCommandHandedOver) {
  RoundTripProbe p;
  p.state_written(5, 4, 1'000'000);
  p.command_handed_over(p.command_accepted(1, 5), 1'025'000);
  p.state_written(6, 5, 1'500'000);
  p.command_handed_over(p.command_accepted(2, 6), 1'540'000);
  const RoundTripStatistics s = p.statistics();
  EXPECT_EQ(s.count, 2u);
  EXPECT_GE(s.p50_us, 25.0);  // the histogram's bucket edge: never below, within 1.6 %
  EXPECT_LT(s.p50_us, 25.0 * 1.016);
  EXPECT_DOUBLE_EQ(s.max_us, 40.0);
}

TEST(RoundTripProbe, CountsTheCyclesUntilTheLoopAppliedTheCommand) {
  RoundTripProbe p;
  p.state_written(5, 4, 1'000'000);
  p.command_handed_over(p.command_accepted(1, 5), 1'025'000);
  p.command_applied(1, 5);  // the next cycle
  p.command_applied(1, 6);  // still the newest applied: counted once
  p.state_written(7, 6, 2'000'000);
  p.command_accepted(2, 7);
  p.command_applied(2, 8);  // two cycles later
  p.state_written(8, 7, 2'500'000);
  p.command_accepted(3, 8);
  p.command_applied(3, 40);  // far later: the last bin
  const RoundTripStatistics s = p.statistics();
  EXPECT_EQ(s.applied_after_cycles[1], 1u);
  EXPECT_EQ(s.applied_after_cycles[2], 1u);
  EXPECT_EQ(s.applied_after_cycles[RoundTripStatistics::kAppliedBins - 1], 1u);
  EXPECT_EQ(s.applied(), 3u);
}

TEST(RoundTripProbe, IgnoresCommandsForStatesItNoLongerKnows) {
  RoundTripProbe p;
  p.state_written(5, 4, 1'000'000);
  p.state_written(5 + 4096, 4100, 9'000'000);  // the same slot, a newer state
  EXPECT_EQ(p.command_accepted(1, 5), 0);      // unknown now
  p.command_handed_over(p.command_accepted(1, 5), 9'500'000);
  EXPECT_EQ(p.command_accepted(2, 0), 0);  // answers no state
  p.command_handed_over(p.command_accepted(3, 0), 9'500'000);
  p.command_applied(1, 4101);
  p.command_applied(7, 4101);  // never accepted
  const RoundTripStatistics s = p.statistics();
  EXPECT_EQ(s.count, 0u);
  EXPECT_EQ(s.applied(), 0u);
}

TEST(RoundTripProbe, DevicesAreSummarisedTogether) {
  RoundTripProbe a, b;
  a.state_written(1, 0, 1'000'000);
  a.command_handed_over(a.command_accepted(1, 1), 1'010'000);
  b.state_written(1, 0, 1'000'000);
  b.command_handed_over(b.command_accepted(1, 1), 1'030'000);
  b.state_written(2, 1, 1'100'000);
  b.command_handed_over(b.command_accepted(2, 2), 1'120'000);
  LatencyHistogram round_trips;
  RoundTripStatistics counts;
  a.merge_into(round_trips, counts);
  b.merge_into(round_trips, counts);
  const RoundTripStatistics s = summarise_round_trips(round_trips, counts);
  EXPECT_EQ(s.count, 3u);
  EXPECT_GE(s.p50_us, 20.0);
  EXPECT_LT(s.p50_us, 20.0 * 1.016);
  EXPECT_DOUBLE_EQ(s.max_us, 30.0);
}

// The publisher writes states while another thread answers them: every sample it takes is consistent (a state
// written at serial * 1000 ns and answered 500 ns later), never a mix of two states sharing a slot.
TEST(RoundTripProbe, ThePublisherAndTheReceiverHandOffConsistently) {
  RoundTripProbe p;
  constexpr std::uint64_t kStates = 200'000;
  std::atomic<std::uint64_t> written{0};
  std::thread publisher([&] {
    for (std::uint64_t serial = 1; serial <= kStates; ++serial) {
      p.state_written(serial, serial - 1, static_cast<std::int64_t>(serial) * 1000);
      written.store(serial, std::memory_order_release);
    }
  });
  std::uint64_t answered = 0;
  while (answered < kStates) {
    const std::uint64_t newest = written.load(std::memory_order_acquire);
    if (newest == answered) {
      std::this_thread::yield();
      continue;
    }
    answered = newest;
    // Also a state about to be overwritten: the one a slot-length before.
    for (std::uint64_t serial : {newest, newest > 4000 ? newest - 4000 : newest}) {
      p.command_handed_over(p.command_accepted(serial, serial), static_cast<std::int64_t>(serial) * 1000 + 500);
    }
  }
  publisher.join();
  LatencyHistogram round_trips;
  RoundTripStatistics counts;
  p.merge_into(round_trips, counts);
  ASSERT_GT(round_trips.count(), 0u);
  EXPECT_EQ(round_trips.min_ns(), 500);  // a newer state's time would make it shorter,
  EXPECT_EQ(round_trips.max_ns(), 500);  // an older one's longer
}

}  // namespace
}  // namespace hapticd::server
