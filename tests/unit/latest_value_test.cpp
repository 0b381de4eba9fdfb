// LatestValue: the reader sees whole values only, each at most once, in publication order, never waiting.
#include "hapticd/realtime/latest_value.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace hapticd {
namespace {

struct Sample {
  std::uint64_t sequence = 0;
  std::uint64_t check = 0;  // ~sequence: a torn copy would break the pair
  double payload[8] = {};
};

TEST(LatestValue, NothingToTakeBeforeAPublish) {
  realtime::LatestValue<Sample> box;
  Sample s;
  EXPECT_FALSE(box.take(s));
  box.publish(Sample{1, ~1ULL, {}});
  EXPECT_TRUE(box.take(s));
  EXPECT_EQ(s.sequence, 1u);
  EXPECT_FALSE(box.take(s)) << "a value is taken once";
}

TEST(LatestValue, ReaderGetsTheNewestOfSeveralPublishes) {
  realtime::LatestValue<Sample> box;
  for (std::uint64_t i = 1; i <= 5; ++i) box.publish(Sample{i, ~i, {}});
  Sample s;
  ASSERT_TRUE(box.take(s));
  EXPECT_EQ(s.sequence, 5u);
}

TEST(LatestValue, ConcurrentWriterAndReaderSeeWholeIncreasingValues) {
  realtime::LatestValue<Sample> box;
  constexpr std::uint64_t kCount = 200000;
  std::thread writer([&] {
    for (std::uint64_t i = 1; i <= kCount; ++i) {
      Sample s{i, ~i, {}};
      for (double& p : s.payload) p = static_cast<double>(i);
      box.publish(s);
    }
  });
  std::uint64_t last = 0, taken = 0;
  Sample s;
  while (last < kCount) {
    if (!box.take(s)) continue;
    ASSERT_EQ(s.check, ~s.sequence);
    for (double p : s.payload) ASSERT_EQ(p, static_cast<double>(s.sequence));
    ASSERT_GT(s.sequence, last);
    last = s.sequence;
    ++taken;
  }
  writer.join();
  EXPECT_GT(taken, 0u);
}

}  // namespace
}  // namespace hapticd
