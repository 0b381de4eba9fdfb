// The DDS bridge's round-trip probe (server/src/dds/round_trip_probe): state written -> command handed to the
// loop, and how many cycles after the state's the loop applied the command; slots reused by newer states are
// never mistaken for the old ones, and the hand-off between the publisher and the receive thread is consistent.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "dds/round_trip_probe.hpp"

namespace hapticd::server {
namespace {

TEST(RoundTripProbe, MeasuresFromTheStateWrittenToTheCommandHandedOver) {
  RoundTripProbe p;
  p.state_written(5, 4, 1'000'000);
  p.command_accepted(1, 5);
  p.command_handed_over(5, 1'025'000);
  p.state_written(6, 5, 1'500'000);
  p.command_accepted(2, 6);
  p.command_handed_over(6, 1'540'000);
  const RoundTripStatistics s = p.statistics();
  EXPECT_EQ(s.count, 2u);
  EXPECT_DOUBLE_EQ(s.p50_us, 25.0);
  EXPECT_DOUBLE_EQ(s.max_us, 40.0);
}

TEST(RoundTripProbe, CountsTheCyclesUntilTheLoopAppliedTheCommand) {
  RoundTripProbe p;
  p.state_written(5, 4, 1'000'000);
  p.command_accepted(1, 5);
  p.command_handed_over(5, 1'025'000);
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
  p.command_accepted(1, 5);
  p.command_handed_over(5, 9'500'000);
  p.command_accepted(2, 0);  // answers no state
  p.command_handed_over(0, 9'500'000);
  p.command_applied(1, 4101);
  p.command_applied(7, 4101);  // never accepted
  const RoundTripStatistics s = p.statistics();
  EXPECT_EQ(s.count, 0u);
  EXPECT_EQ(s.applied(), 0u);
}

TEST(RoundTripProbe, DevicesAreSummarisedTogether) {
  RoundTripProbe a, b;
  a.state_written(1, 0, 0);
  a.command_accepted(1, 1);
  a.command_handed_over(1, 10'000);
  b.state_written(1, 0, 0);
  b.command_accepted(1, 1);
  b.command_handed_over(1, 30'000);
  b.state_written(2, 1, 100'000);
  b.command_accepted(2, 2);
  b.command_handed_over(2, 120'000);
  std::vector<std::int64_t> samples;
  RoundTripStatistics counts;
  a.merge_into(samples, counts);
  b.merge_into(samples, counts);
  const RoundTripStatistics s = summarise_round_trips(samples, counts);
  EXPECT_EQ(s.count, 3u);
  EXPECT_DOUBLE_EQ(s.p50_us, 20.0);
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
      p.command_accepted(serial, serial);
      p.command_handed_over(serial, static_cast<std::int64_t>(serial) * 1000 + 500);
    }
  }
  publisher.join();
  const RoundTripStatistics s = p.statistics();
  ASSERT_GT(s.count, 0u);
  EXPECT_DOUBLE_EQ(s.p50_us, 0.5);
  EXPECT_DOUBLE_EQ(s.max_us, 0.5);
}

}  // namespace
}  // namespace hapticd::server
