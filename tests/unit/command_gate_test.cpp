// The engine-command gate (server/src/dds/command_gate) and the content checks it relies on
// (dds/command_validation): ownership, order, freshness, and a bounded randomised fuzz of the content checks
// (fixed seed) - no input may crash them or pass with non-finite or out-of-bounds content.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "dds/command_gate.hpp"
#include "hapticd/dds/conversion.hpp"

namespace hapticd::server {
namespace {

using dds::RejectReason;

constexpr std::int64_t kNow = 1'800'000'000'000'000'000;

hapticd_msg_EngineCommand command(const char* engine, std::uint64_t serial) {
  hapticd_msg_EngineCommand c{};
  dds::set_text(c.device, "v3");
  dds::set_text(c.engine, engine);
  c.serial = serial;
  c.kind = hapticd_msg_COMMAND_COUPLING;
  c.pose.position[0] = 0.1;
  c.pose.orientation[0] = 1.0;
  c.anchor.orientation[0] = 1.0;
  return c;
}

TEST(CommandGate, OnlyTheOwnerIsHeardAndOnlyInOrderAndFresh) {
  CommandGate gate(dds::CommandBounds{}, 0.1);
  EXPECT_EQ(gate.admit(command("a", 1), kNow, kNow).reason, RejectReason::not_owner);  // nobody claimed yet
  EXPECT_TRUE(gate.claim("a"));
  EXPECT_FALSE(gate.claim("b"));
  EXPECT_TRUE(gate.claim("a"));  // re-claiming one's own device is fine
  EXPECT_TRUE(gate.admit(command("a", 1), kNow, kNow).accepted);
  EXPECT_EQ(gate.admit(command("a", 1), kNow, kNow).reason, RejectReason::out_of_order);
  EXPECT_EQ(gate.admit(command("b", 2), kNow, kNow).reason, RejectReason::not_owner);
  EXPECT_EQ(gate.admit(command("a", 3), kNow - 200'000'000, kNow).reason, RejectReason::stale);
  EXPECT_EQ(gate.admit(command("a", 4), kNow + 200'000'000, kNow).reason, RejectReason::stale);  // from the future
  EXPECT_TRUE(gate.admit(command("a", 5), kNow - 50'000'000, kNow).accepted);
  EXPECT_FALSE(gate.release("b"));
  EXPECT_TRUE(gate.release("a"));
  EXPECT_TRUE(gate.claim("b"));
  EXPECT_TRUE(gate.admit(command("b", 1), kNow, kNow).accepted);  // a new claim restarts the serials
  EXPECT_EQ(gate.accepted(), 3u);
  EXPECT_EQ(gate.rejected_total(), 5u);
  EXPECT_EQ(gate.received(), 8u);
}

TEST(CommandValidation, EachKindIsCheckedForItsOwnFields) {
  const dds::CommandBounds b;
  auto c = command("a", 1);
  EXPECT_TRUE(dds::check_command_content(c, b).ok);
  c.pose.orientation[0] = 0.0;
  EXPECT_EQ(dds::check_command_content(c, b).reason, RejectReason::malformed);
  c = command("a", 1);
  c.twist[0] = 100.0;
  EXPECT_EQ(dds::check_command_content(c, b).reason, RejectReason::out_of_bounds);
  c = command("a", 1);
  c.kind = hapticd_msg_COMMAND_WRENCH;
  c.wrench[2] = 301.0;
  EXPECT_EQ(dds::check_command_content(c, b).reason, RejectReason::out_of_bounds);
  c.wrench[2] = 30.0;
  c.local_model = true;
  c.stiffness[0] = -1.0;  // a negative stiffness would be active
  EXPECT_EQ(dds::check_command_content(c, b).reason, RejectReason::out_of_bounds);
  c.stiffness[0] = 1000.0;
  EXPECT_TRUE(dds::check_command_content(c, b).ok);
  c.damping[4] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(dds::check_command_content(c, b).reason, RejectReason::non_finite);
  c = command("a", 0);  // serials start at 1
  EXPECT_EQ(dds::check_command_content(c, b).reason, RejectReason::malformed);
  c = command("a", 1);
  std::memset(c.engine, 'x', sizeof c.engine);  // no terminating NUL
  EXPECT_EQ(dds::check_command_content(c, b).reason, RejectReason::malformed);
}

TEST(CommandValidation, RandomisedSamplesNeverPassWithBadContent) {
  // Bounded randomised fuzz (fixed seed): random bytes, and valid commands with random fields broken.
  std::mt19937_64 rng(20261123);
  const dds::CommandBounds b;
  std::uniform_int_distribution<int> byte(0, 255);
  std::size_t accepted = 0;
  for (int i = 0; i < 200000; ++i) {
    hapticd_msg_EngineCommand c{};
    if (i % 2 == 0) {
      auto* raw = reinterpret_cast<unsigned char*>(&c);
      for (std::size_t k = 0; k < sizeof c; ++k) raw[k] = static_cast<unsigned char>(byte(rng));
    } else {
      c = command("a", 1 + static_cast<std::uint64_t>(i));
      c.kind = static_cast<hapticd_msg_CommandKind>(i % 3);
      double* fields = &c.wrench[0];
      const double specials[] = {std::nan(""), std::numeric_limits<double>::infinity(), -1e300, 1e9, -5.0, 0.5};
      fields[rng() % 6] = specials[rng() % 6];
      c.pose.position[rng() % 3] = specials[rng() % 6];
    }
    const dds::ContentCheck r = dds::check_command_content(c, b);
    if (!r.ok) continue;
    ++accepted;
    // Whatever passed is finite, bounded and turns into finite engine input with unit quaternions.
    const EngineInput e = dds::to_engine_input(c);
    ASSERT_TRUE(e.wrench.force.allFinite() && e.wrench.torque.allFinite());
    ASSERT_LE(e.wrench.force.norm(), b.max_force_n);
    ASSERT_TRUE(e.proxy_pose.position.allFinite() && e.motion_pose.position.allFinite());
    if (e.has_proxy) {
      ASSERT_NEAR(e.proxy_pose.orientation.norm(), 1.0, 1e-9);
    }
    ASSERT_LE(e.proxy_pose.position.norm(), b.max_distance_m);
    ASSERT_TRUE(e.stiffness.allFinite() && (e.stiffness.array() >= 0.0).all());
  }
  EXPECT_GT(accepted, 0u);  // the fuzz did reach the accepting paths
}

TEST(Conversion, BoundedTextsNeverOverrun) {
  char name[8];
  dds::set_text(name, "a-long-device-name");
  EXPECT_EQ(dds::text_of(name), "a-long-");
  std::memset(name, 'x', sizeof name);
  EXPECT_EQ(dds::text_of(name).size(), sizeof name);  // unterminated: stops at the end
  EXPECT_FALSE(dds::terminated(name));
}

}  // namespace
}  // namespace hapticd::server
