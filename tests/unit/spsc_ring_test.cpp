#include "hapticd/realtime/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace hapticd::realtime {
namespace {

TEST(SpscRing, FifoAndFullEmpty) {
  SpscRing<int> ring(3);  // rounds up to 4
  EXPECT_EQ(ring.capacity(), 4u);
  int out = 0;
  EXPECT_FALSE(ring.try_pop(out));
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.try_push(i));
  EXPECT_FALSE(ring.try_push(99));
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(ring.try_pop(out));
    EXPECT_EQ(out, i);
  }
  EXPECT_FALSE(ring.try_pop(out));
}

// Two threads, a million items: every item arrives once and in order (run under the tsan preset too).
TEST(SpscRing, HandsOffBetweenThreadsInOrder) {
  constexpr int kItems = 1'000'000;
  SpscRing<int> ring(256);
  std::thread producer([&] {
    for (int i = 0; i < kItems; ++i)
      while (!ring.try_push(i)) std::this_thread::yield();
  });
  int expected = 0;
  int value = 0;
  while (expected < kItems) {
    if (ring.try_pop(value)) {
      ASSERT_EQ(value, expected);
      ++expected;
    } else {
      std::this_thread::yield();
    }
  }
  producer.join();
  EXPECT_FALSE(ring.try_pop(value));
}

}  // namespace
}  // namespace hapticd::realtime
