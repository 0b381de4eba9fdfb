// The engine input's weight (server/src/session/engine_input_port): fresh until the deadline, then a linear
// fade to zero; input that starts after a silence ramps in - and the port that applies it each cycle.
#include "session/engine_input_port.hpp"

#include <gtest/gtest.h>

namespace hapticd::server {
namespace {

constexpr double kPeriod = 0.0005;
const EngineTiming kTiming{0.05, 0.02, 0.1};

TEST(EngineWeight, FreshInputRampsInThenHoldsThenFadesAfterTheDeadline) {
  // Ramp-in: 0.1 s = 200 cycles from zero to one, one step per cycle, never above the target.
  double w = 0.0;
  for (int k = 1; k <= 200; ++k) {
    w = engine_weight(0.0, w, kPeriod, kTiming);
    ASSERT_NEAR(w, k * kPeriod / 0.1, 1e-12) << k;
  }
  EXPECT_DOUBLE_EQ(engine_weight(0.0, 1.0, kPeriod, kTiming), 1.0);
  EXPECT_DOUBLE_EQ(engine_weight(0.05, 1.0, kPeriod, kTiming), 1.0);  // at the deadline: still fresh
  // After the deadline: a linear fade over 20 ms, at once (no ramp downwards).
  EXPECT_NEAR(engine_weight(0.06, 1.0, kPeriod, kTiming), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(engine_weight(0.07, 1.0, kPeriod, kTiming), 0.0);
  EXPECT_DOUBLE_EQ(engine_weight(5.0, 1.0, kPeriod, kTiming), 0.0);
  // Input that comes back after a silence ramps in from where the weight was.
  EXPECT_NEAR(engine_weight(0.0, 0.0, kPeriod, kTiming), kPeriod / 0.1, 1e-12);
}

TEST(EngineInputPort, WeightsTheNewestInputByItsAgeAndRampsInAfterARestart) {
  EngineInputPort port(kTiming);
  const auto at = [](std::int64_t k) { return CycleTime{k * 500'000, 500'000, static_cast<std::uint64_t>(k)}; };
  port.take(at(0));
  EXPECT_EQ(port.input().weight, 0.0);  // nothing has arrived
  EXPECT_FALSE(port.stale());
  EngineInput in;
  in.sequence = 7;
  in.has_wrench = true;
  port.publish(in);
  port.take(at(1));
  EXPECT_EQ(port.input().sequence, 7u);
  EXPECT_NEAR(port.input().weight, kPeriod / 0.1, 1e-12);
  for (int k = 2; k <= 300; ++k) port.take(at(k));  // no new input: fresh for 50 ms, then fading
  EXPECT_TRUE(port.stale());
  EXPECT_EQ(port.input().weight, 0.0);  // 150 ms old
  port.restart();
  port.take(at(301));
  EXPECT_EQ(port.input().weight, 0.0);
  EXPECT_FALSE(port.stale());
}

// A clean release (hapticctl release, Client::release): the forces fade out at once over the fade time, as
// after a missed deadline, but the engine is never flagged stale; a new owner's input ramps in and can go stale.
TEST(EngineInputPort, AReleasedEngineFadesOutWithoutBeingStale) {
  EngineInputPort port(kTiming);
  const auto at = [](std::int64_t k) { return CycleTime{k * 500'000, 500'000, static_cast<std::uint64_t>(k)}; };
  EngineInput in;
  in.sequence = 1;
  in.has_wrench = true;
  std::int64_t k = 0;
  for (; k < 300; ++k) {  // fresh input every cycle: ramped in to full weight
    in.sequence = static_cast<std::uint64_t>(k + 1);
    port.publish(in);
    port.take(at(k));
  }
  EXPECT_EQ(port.input().weight, 1.0);
  port.publish(in);  // the engine's last command and its release reach the same cycle
  port.end();
  port.take(at(k++));
  EXPECT_LT(port.input().weight, 1.0);  // the fade started at once ...
  EXPECT_GT(port.input().weight, 0.9);  // ... and is a fade, not a step
  EXPECT_FALSE(port.stale());
  for (int n = 0; n < 400; ++n, ++k) {
    port.take(at(k));
    ASSERT_FALSE(port.stale()) << n;
  }
  EXPECT_EQ(port.input().weight, 0.0);  // gone after the fade time (20 ms = 40 cycles)
  in.sequence = 1000;                   // the next owner
  port.publish(in);
  port.take(at(k++));
  EXPECT_NEAR(port.input().weight, kPeriod / 0.1, 1e-12);
  for (int n = 0; n < 300; ++n, ++k) port.take(at(k));
  EXPECT_TRUE(port.stale());  // it went silent without a release
  port.end();                 // a release when nothing has been seen since a restart changes nothing
  port.restart();
  port.end();
  port.take(at(k++));
  EXPECT_FALSE(port.stale());
  EXPECT_EQ(port.input().weight, 0.0);
}

}  // namespace
}  // namespace hapticd::server
