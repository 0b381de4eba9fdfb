// The engines' worlds in the live view: a world on hapticd_world is checked (dds::check_world: a malformed one is
// never drawn) and turned into one scene entity per engine on /world/scene (live_view/world_view), deleted when the
// engine falls silent.
#include "live_view/world_view.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/world_validation.hpp"

namespace hapticd::server::live_view {
namespace {

constexpr std::int64_t kSecond = 1'000'000'000;

// A world of `engine` with a 2 x 4 x 6 cm box and a 1 cm ball, serial `serial`.
std::unique_ptr<hapticd_msg_World> world(const std::string& engine, std::uint64_t serial = 1) {
  auto w = std::make_unique<hapticd_msg_World>();
  dds::set_text(w->engine, engine);
  w->serial = serial;
  w->shape_count = 2;
  for (int i = 0; i < 2; ++i) {
    hapticd_msg_WorldShape& s = w->shapes[i];
    dds::set_text(s.body, i == 0 ? "block" : "proxy");
    s.shape = i == 0 ? hapticd_msg_SHAPE_BOX : hapticd_msg_SHAPE_SPHERE;
    s.size[0] = i == 0 ? 0.01 : 0.01;
    s.size[1] = i == 0 ? 0.02 : 0.0;
    s.size[2] = i == 0 ? 0.03 : 0.0;
    for (double& c : s.color) c = 0.5;
    s.shape_pose.position[0] = 0.1 * i;
    s.shape_pose.orientation[0] = 1.0;
  }
  return w;
}

TEST(WorldView, AMalformedWorldIsRefusedWithTheReason) {
  EXPECT_EQ(dds::check_world(*world("engine")), "");
  const auto broken = [](auto change) {
    auto w = world("engine");
    change(*w);
    return std::string(dds::check_world(*w));
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(broken([](hapticd_msg_World& w) { w.engine[0] = '\0'; }), "");
  EXPECT_NE(broken([](hapticd_msg_World& w) { std::fill(std::begin(w.engine), std::end(w.engine), 'x'); }), "");
  EXPECT_NE(broken([](hapticd_msg_World& w) { w.shape_count = -1; }), "");
  EXPECT_NE(broken([](hapticd_msg_World& w) { w.shape_count = hapticd_msg_MAX_WORLD_SHAPES + 1; }), "");
  EXPECT_NE(broken([](hapticd_msg_World& w) { w.shapes[1].shape = 6; }), "");
  EXPECT_NE(broken([&](hapticd_msg_World& w) { w.shapes[1].size[0] = nan; }), "");
  EXPECT_NE(broken([](hapticd_msg_World& w) { w.shapes[1].size[0] = -0.1; }), "");
  EXPECT_NE(broken([](hapticd_msg_World& w) { w.shapes[0].color[3] = 2.0; }), "");
  EXPECT_NE(broken([](hapticd_msg_World& w) { w.shapes[0].shape_pose.position[2] = 1e6; }), "");
  EXPECT_NE(broken([](hapticd_msg_World& w) { w.shapes[0].shape_pose.orientation[0] = 0.0; }), "");
  EXPECT_NE(
      broken([](hapticd_msg_World& w) { std::fill(std::begin(w.shapes[0].body), std::end(w.shapes[0].body), 'b'); }),
      "");
  // A shape past the count is not looked at.
  EXPECT_EQ(broken([&](hapticd_msg_World& w) { w.shapes[5].size[0] = nan; }), "");
}

TEST(WorldView, EachEngineIsOneEntityUpdatedWhenItsWorldChangesAndDeletedWhenItFallsSilent) {
  WorldView view;
  std::string out;
  EXPECT_FALSE(view.scene_update(1, 0, out));  // nothing yet
  view.take(*world("mujoco"), 1 * kSecond);
  ASSERT_TRUE(view.scene_update(1, 1 * kSecond, out));
  EXPECT_NE(out.find("\"id\":\"world/mujoco\""), std::string::npos) << out;
  EXPECT_NE(out.find("\"cubes\":[{"), std::string::npos) << out;
  EXPECT_NE(out.find("\"size\":{\"x\":0.02,\"y\":0.04,\"z\":0.06}"), std::string::npos) << out;  // full extents
  EXPECT_NE(out.find("\"spheres\":[{"), std::string::npos) << out;
  EXPECT_NE(out.find("\"deletions\":[]"), std::string::npos) << out;
  EXPECT_FALSE(view.scene_update(2, static_cast<std::int64_t>(1.5 * kSecond), out));  // unchanged
  view.take(*world("mujoco", 1), static_cast<std::int64_t>(1.6 * kSecond));           // a repeat: not new
  EXPECT_FALSE(view.scene_update(2, static_cast<std::int64_t>(1.7 * kSecond), out));
  view.take(*world("mujoco", 2), static_cast<std::int64_t>(1.8 * kSecond));
  EXPECT_TRUE(view.scene_update(3, static_cast<std::int64_t>(1.9 * kSecond), out));
  // Silent for more than 2 s: deleted.
  ASSERT_TRUE(view.scene_update(4, static_cast<std::int64_t>(4.0 * kSecond), out));
  EXPECT_NE(out.find("\"deletions\":[{\"timestamp\":{\"sec\":0,\"nsec\":4},\"type\":0,\"id\":\"world/mujoco\"}]"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("\"entities\":[]"), std::string::npos) << out;
  EXPECT_EQ(view.taken(), 2u);
}

TEST(WorldView, NoMoreThanSixteenEnginesAtOnce) {
  WorldView view;
  for (int e = 0; e < 20; ++e) view.take(*world("engine" + std::to_string(e)), kSecond);
  EXPECT_EQ(view.taken(), WorldView::kMaxEngines);
  EXPECT_EQ(view.dropped(), 4u);
}

}  // namespace
}  // namespace hapticd::server::live_view
