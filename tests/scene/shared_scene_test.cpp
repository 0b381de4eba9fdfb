// One scene for several devices, edited while they render it (scene/shared_scene.hpp): every reader takes every
// edit, and its refresh, the proxy's rebind and update allocate nothing while an editor thread adds, re-materials
// and removes objects; a proxy pressed on an object keeps its contact across an edit of another object; an object
// made around the proxy is left out until the proxy has left it (no kick); moves are played back, and a pose sent
// to a removed object never reaches the next object in its slot; bad edits are refused with the reason.
#include "hapticd/scene/shared_scene.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "hapticd/scene/proxy.hpp"
#include "hapticd/testing/allocation_guard.hpp"

namespace hapticd::scene {
namespace {

constexpr std::int64_t kPeriodNs = 500'000;  // 2 kHz

SceneObject floor_object() {
  SceneObject o;
  o.name = "floor";
  o.shape.kind = ShapeKind::plane;
  o.material.stiffness_n_per_m = 2000.0;
  o.material.damping_n_s_per_m = 0.0;
  return o;  // the plane z = 0, its outside z > 0
}

SceneObject sphere(const std::string& name, const Eigen::Vector3d& at, double radius, bool moving = false) {
  SceneObject o;
  o.name = name;
  o.shape.kind = ShapeKind::sphere;
  o.shape.radius = radius;
  o.pose.translation() = at;
  o.material.stiffness_n_per_m = 1000.0;
  o.material.damping_n_s_per_m = 0.0;
  o.moving = moving;
  return o;
}

ProxySettings settings() {
  ProxySettings s;
  s.radius_m = 0.005;
  return s;
}

// A device's loop: refresh, rebind when the scene changed, update.
struct Device {
  explicit Device(SharedScene& shared) : reader(shared.add_reader()) {
    reader.refresh(0);
    proxy.configure(settings(), reader.scene());
  }
  const ProxyState& cycle(std::int64_t now_ns, const Eigen::Vector3d& goal) {
    if (reader.refresh(now_ns)) proxy.rebind(reader.scene());
    return proxy.update(goal, Eigen::Vector3d::Zero());
  }
  SharedScene::Reader& reader;
  GodObject proxy;
};

TEST(SharedScene, EveryReaderTakesEveryEditWithoutAllocatingWhileAnEditorThreadEdits) {
  SharedScene shared(Scene{{floor_object()}});
  Device a(shared), b(shared);
  const Eigen::Vector3d pressed(0.0, 0.0, 0.002);  // 3 mm into the floor (the proxy's radius is 5 mm)
  a.proxy.reset(Eigen::Vector3d(0, 0, 0.02));
  b.proxy.reset(Eigen::Vector3d(0, 0, 0.02));
  std::atomic<bool> done{false};
  std::atomic<int> edits{0};
  std::thread editor([&] {
    for (int k = 0; k < 200; ++k) {
      shared.add(sphere("ball" + std::to_string(k), Eigen::Vector3d(0.2, 0.0, 0.05), 0.01));
      Material m;
      m.stiffness_n_per_m = 1500.0 + k;
      shared.set_material("ball" + std::to_string(k), m);
      if (k >= 5) shared.remove("ball" + std::to_string(k - 5));
      edits += 3 - (k >= 5 ? 0 : 1);
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    done = true;
  });
  std::size_t allocations = 0;
  double lowest_force = 1e9, highest_force = 0.0;
  std::int64_t now = 0;
  for (int k = 0; !done || k < 100; ++k) {
    now += kPeriodNs;
    const Eigen::Vector3d goal = k < 20 ? Eigen::Vector3d(0, 0, 0.02 - 0.0009 * k) : pressed;
    allocations += testing::count_allocations([&] {
      a.cycle(now, goal);
      b.cycle(now, goal);
    });
    if (k >= 40) {
      lowest_force = std::min({lowest_force, a.proxy.state().force.z(), b.proxy.state().force.z()});
      highest_force = std::max({highest_force, a.proxy.state().force.z(), b.proxy.state().force.z()});
    }
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
  editor.join();
  a.cycle(now + kPeriodNs, pressed);
  b.cycle(now + kPeriodNs, pressed);
  if (testing::AllocationGuard::available()) EXPECT_EQ(allocations, 0u);
  // Each reader took scenes while the editor edited, and ends on the newest: the last five balls and the floor.
  EXPECT_GT(a.reader.scenes_taken(), 10u);
  EXPECT_GT(b.reader.scenes_taken(), 10u);
  ASSERT_EQ(a.reader.scene().objects.size(), 6u);
  EXPECT_EQ(a.reader.scene().objects.back().name, "ball199");
  EXPECT_EQ(a.reader.scene().objects.back().material.stiffness_n_per_m, 1699.0);
  EXPECT_EQ(shared.snapshot().objects.size(), 6u);
  // The floor was felt all along, 2000 N/m x 3 mm, through every swap.
  EXPECT_NEAR(lowest_force, 6.0, 1e-3);
  EXPECT_NEAR(highest_force, 6.0, 1e-3);
  std::printf("%d edits; reader a took %llu scenes, b %llu\n", edits.load(),
              static_cast<unsigned long long>(a.reader.scenes_taken()),
              static_cast<unsigned long long>(b.reader.scenes_taken()));
}

TEST(SharedScene, AnObjectMadeAroundTheProxyIsLeftOutUntilTheProxyHasLeftIt) {
  SharedScene shared;
  Device d(shared);
  const Eigen::Vector3d hand(0.0, 0.0, 0.0);
  d.proxy.reset(hand);
  std::int64_t now = kPeriodNs;
  EXPECT_EQ(d.cycle(now, hand).force.norm(), 0.0);
  shared.add(sphere("bubble", hand, 0.02));  // the hand is in its middle
  now += kPeriodNs;
  EXPECT_EQ(d.cycle(now, hand).force.norm(), 0.0) << "a ball made around the hand does not kick it";
  // Out of it (beyond its surface and the proxy's radius) and back in: now it holds the proxy at its surface.
  for (int k = 1; k <= 60; ++k) d.cycle(now += kPeriodNs, Eigen::Vector3d(0.0, 0.0, 0.001 * k));
  for (int k = 60; k >= 20; --k) d.cycle(now += kPeriodNs, Eigen::Vector3d(0.0, 0.0, 0.001 * k));
  const ProxyState& s = d.cycle(now += kPeriodNs, Eigen::Vector3d(0.0, 0.0, 0.022));
  EXPECT_NEAR(s.proxy.z(), 0.025, 1e-5);
  EXPECT_NEAR(s.force.z(), 1000.0 * 0.003, 1e-3);
}

TEST(SharedScene, AProxyOnAnObjectKeepsItsContactWhenAnotherObjectIsRemovedBeforeIt) {
  SharedScene shared;
  shared.add(sphere("first", Eigen::Vector3d(0.5, 0.0, 0.0), 0.01));
  shared.add(floor_object());
  Device d(shared);
  std::int64_t now = 0;
  d.proxy.reset(Eigen::Vector3d(0, 0, 0.02));
  for (int k = 0; k <= 20; ++k) d.cycle(now += kPeriodNs, Eigen::Vector3d(0, 0, 0.02 - 0.0009 * k));
  EXPECT_NEAR(d.proxy.state().force.z(), 6.0, 1e-3);
  shared.remove("first");  // the floor's index changes from 1 to 0
  const ProxyState& s = d.cycle(now += kPeriodNs, Eigen::Vector3d(0, 0, 0.002));
  EXPECT_EQ(d.reader.scene().objects.size(), 1u);
  EXPECT_NEAR(s.proxy.z(), 0.005, 1e-6) << "the proxy stays on the floor";
  EXPECT_NEAR(s.force.z(), 6.0, 1e-3);
}

TEST(SharedScene, MovesArePlayedBackAndAPoseForARemovedObjectNeverReachesTheNextInItsSlot) {
  SharedScene shared;
  shared.add(sphere("puck", Eigen::Vector3d(0.0, 0.0, 0.0), 0.01, true));
  Device d(shared);
  std::int64_t now = 0;
  const Eigen::Vector3d far(1.0, 1.0, 1.0);
  d.cycle(now += kPeriodNs, far);
  PoseUpdate to;
  to.position = Eigen::Vector3d(0.1, 0.0, 0.0);
  shared.move("puck", to);
  d.cycle(now += kPeriodNs, far);
  // 30 Hz updates: the puck glides over one interval (33 ms by default), never jumps.
  double largest_step = 0.0, previous = 0.0;
  for (int k = 0; k < 200; ++k) {
    d.cycle(now += kPeriodNs, far);
    const double x = d.reader.scene().objects[0].pose.translation().x();
    largest_step = std::max(largest_step, std::abs(x - previous));
    previous = x;
  }
  EXPECT_NEAR(previous, 0.1, 1e-9);
  EXPECT_LT(largest_step, 0.002) << "0.1 m over 33 ms is 1.5 mm a cycle at 2 kHz";
  // A pose sent to the puck, then the puck removed and another moving object made in its slot before the loop
  // looked: the new one stays where it was made.
  to.position = Eigen::Vector3d(-0.3, 0.0, 0.0);
  shared.move("puck", to);
  shared.remove("puck");
  shared.add(sphere("next", Eigen::Vector3d(0.0, 0.2, 0.0), 0.01, true));
  for (int k = 0; k < 200; ++k) d.cycle(now += kPeriodNs, far);
  ASSERT_EQ(d.reader.scene().objects.size(), 1u);
  EXPECT_EQ(d.reader.scene().objects[0].slot, 0u);
  EXPECT_NEAR(d.reader.scene().objects[0].pose.translation().x(), 0.0, 1e-12);
  EXPECT_NEAR(d.reader.scene().objects[0].pose.translation().y(), 0.2, 1e-12);
}

TEST(SharedScene, BadEditsAreRefusedWithTheReasonAndChangeNothing) {
  SharedScene shared;
  shared.add(sphere("ball", Eigen::Vector3d::Zero(), 0.01));
  auto refused = [&](auto&& edit, const std::string& reason) {
    try {
      edit();
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "not refused: " << reason;
  };
  refused([&] { shared.add(sphere("ball", Eigen::Vector3d::Zero(), 0.01)); }, "'ball' is taken");
  refused([&] { shared.add(sphere("", Eigen::Vector3d::Zero(), 0.01)); }, "needs a name");
  refused([&] { shared.remove("nobody"); }, "no object named 'nobody'");
  refused([&] { shared.move("ball", PoseUpdate{}); }, "not made a moving object");
  refused([&] { shared.set_material("nobody", Material{}); }, "no object named 'nobody'");
  for (std::size_t k = 1; k < SharedScene::kMaxObjects; ++k)
    shared.add(sphere("b" + std::to_string(k), Eigen::Vector3d(0.1 * static_cast<double>(k), 0, 0), 0.01));
  refused([&] { shared.add(sphere("one-more", Eigen::Vector3d::Zero(), 0.01)); }, "the scene is full (1024 objects)");
  EXPECT_EQ(shared.snapshot().objects.size(), SharedScene::kMaxObjects);
}

}  // namespace
}  // namespace hapticd::scene
