// The engine-command gate (server/src/gate/command_gate) and the content checks it relies on
// (dds/command_validation): ownership, order, freshness, and a bounded randomised fuzz of the content checks
// (fixed seed) - no input may crash them or pass with non-finite or out-of-bounds content.
#include "gate/command_gate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

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
  c.command_pose.position[0] = 0.1;
  c.command_pose.orientation[0] = 1.0;
  c.anchor.orientation[0] = 1.0;
  return c;
}

// A participant (by its GUID's first byte) and one of its writers.
PeerId peer(unsigned char n) {
  std::array<unsigned char, 16> guid{};
  guid[0] = n;
  return PeerId::dds_participant(guid);
}
Sender from(unsigned char participant, std::uint64_t writer) { return Sender{peer(participant), writer}; }

TEST(CommandGate, OnlyTheOwnerIsHeardAndOnlyInOrderAndFresh) {
  CommandGate gate(dds::CommandBounds{}, 0.1);
  const Sender a = from(1, 11), b = from(2, 21);
  EXPECT_EQ(gate.admit(command("a", 1), a, kNow, kNow).reason, RejectReason::not_owner);  // nobody claimed yet
  EXPECT_TRUE(gate.claim("a", peer(1)));
  EXPECT_FALSE(gate.claim("b", peer(2)));
  EXPECT_TRUE(gate.claim("a", peer(1)));  // re-claiming one's own device is fine
  EXPECT_TRUE(gate.admit(command("a", 1), a, kNow, kNow).accepted);
  EXPECT_EQ(gate.admit(command("a", 1), a, kNow, kNow).reason, RejectReason::out_of_order);
  EXPECT_EQ(gate.admit(command("b", 2), b, kNow, kNow).reason, RejectReason::not_owner);
  EXPECT_EQ(gate.admit(command("a", 3), a, kNow - 200'000'000, kNow).reason, RejectReason::stale);
  EXPECT_EQ(gate.admit(command("a", 4), a, kNow + 200'000'000, kNow).reason, RejectReason::stale);  // from the future
  EXPECT_TRUE(gate.admit(command("a", 5), a, kNow - 50'000'000, kNow).accepted);
  EXPECT_FALSE(gate.release(peer(2)));
  EXPECT_TRUE(gate.release(peer(1)));
  EXPECT_TRUE(gate.claim("b", peer(2)));
  EXPECT_TRUE(gate.admit(command("b", 1), b, kNow, kNow).accepted);  // a new claim restarts the serials
  EXPECT_EQ(gate.accepted(), 3u);
  EXPECT_EQ(gate.rejected_total(), 5u);
  EXPECT_EQ(gate.received(), 8u);
}

TEST(CommandGate, TheOwnersIdFromAnotherParticipantIsNotTheOwner) {
  // The attack: a second process writes under the owner's client id with a serial near 2^64, and asks to
  // release the device or claims it under the same id.
  CommandGate gate(dds::CommandBounds{}, 0.1);
  ASSERT_TRUE(gate.claim("engine", peer(1)));
  const Sender owner = from(1, 11), spoofer = from(2, 21);
  EXPECT_TRUE(gate.admit(command("engine", 1), owner, kNow, kNow).accepted);
  EXPECT_EQ(gate.admit(command("engine", ~std::uint64_t{0} - 5), spoofer, kNow, kNow).reason, RejectReason::not_owner);
  EXPECT_FALSE(gate.claim("engine", peer(2)));
  EXPECT_FALSE(gate.release(peer(2)));
  EXPECT_TRUE(gate.owned_by(peer(1)));
  EXPECT_FALSE(gate.owned_by(peer(2)));
  // The owner's own serials go on: the spoofer's huge serial was never recorded.
  EXPECT_TRUE(gate.admit(command("engine", 2), owner, kNow, kNow).accepted);
  // The owner's participant under another client id is not the claim either.
  EXPECT_EQ(gate.admit(command("other", 3), owner, kNow, kNow).reason, RejectReason::not_owner);
  EXPECT_FALSE(gate.claim("other", peer(1)));
  // A writer whose participant is unknown (no longer matched) is nobody.
  EXPECT_EQ(gate.admit(command("engine", 4), Sender{PeerId{}, 99}, kNow, kNow).reason, RejectReason::not_owner);
  EXPECT_EQ(gate.rejected()[static_cast<std::size_t>(RejectReason::not_owner)], 3u);
}

TEST(CommandGate, SerialsAreOrderedPerWriterOfTheOwner) {
  CommandGate gate(dds::CommandBounds{}, 0.1);
  ASSERT_TRUE(gate.claim("engine", peer(1)));
  const Sender first = from(1, 11), second = from(1, 12);
  EXPECT_TRUE(gate.admit(command("engine", 100), first, kNow, kNow).accepted);
  EXPECT_TRUE(gate.admit(command("engine", 1), second, kNow, kNow).accepted);  // its own sequence
  EXPECT_EQ(gate.admit(command("engine", 100), first, kNow, kNow).reason, RejectReason::out_of_order);
  EXPECT_TRUE(gate.admit(command("engine", 2), second, kNow, kNow).accepted);
  // The table is bounded: more writers than it holds evict the least recently used, never grow it.
  for (dds_instance_handle_t w = 100; w < 100 + 4 * CommandGate::kWriters; ++w)
    EXPECT_TRUE(gate.admit(command("engine", 5), from(1, w), kNow, kNow).accepted);
  EXPECT_TRUE(gate.admit(command("engine", 6), from(1, 100 + 4 * CommandGate::kWriters - 1), kNow, kNow).accepted);
  EXPECT_EQ(gate.admit(command("engine", 6), from(1, 100 + 4 * CommandGate::kWriters - 1), kNow, kNow).reason,
            RejectReason::out_of_order);
}

TEST(CommandValidation, EachKindIsCheckedForItsOwnFields) {
  const dds::CommandBounds b;
  auto c = command("a", 1);
  EXPECT_TRUE(dds::check_command_content(c, b).ok);
  c.command_pose.orientation[0] = 0.0;
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

TEST(CommandValidation, PoseDistancesAreTakenFromTheDevicesBase) {
  dds::CommandBounds b;  // 2 m
  b.base_position = {3.0, 0.0, 0.0};
  auto c = command("a", 1);
  c.command_pose.position[0] = 4.5;  // 1.5 m from the base, 4.5 m from the world's origin
  EXPECT_TRUE(dds::check_command_content(c, b).ok);
  c.command_pose.position[0] = 0.5;  // 2.5 m from the base
  EXPECT_EQ(dds::check_command_content(c, b).reason, RejectReason::out_of_bounds);
  c = command("a", 1);
  c.kind = hapticd_msg_COMMAND_WRENCH;
  c.local_model = true;
  c.anchor.position[0] = 0.5;
  EXPECT_EQ(dds::check_command_content(c, b).reason, RejectReason::out_of_bounds);
  c.anchor.position[0] = 4.0;
  EXPECT_TRUE(dds::check_command_content(c, b).ok);
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
      c.command_pose.position[rng() % 3] = specials[rng() % 6];
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
