// Objects a rendering engine moves at its own rate (scene/pose_track.hpp): a box the engine moves at 30 Hz
// (updates with jitter), pressed by a hand that holds still, shows no force step above 0.2 N at the updates -
// where the same box held at each update's pose (what the hand feels from an engine's proxy today) steps by over
// 1 N; the moving box pushes the hand and never swallows the proxy; the track stops at the last pose when updates
// stop; playing it back allocates nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "hapticd/scene/pose_track.hpp"
#include "hapticd/scene/proxy.hpp"
#include "hapticd/testing/allocation_guard.hpp"

namespace hapticd::scene {
namespace {

constexpr std::int64_t kPeriodNs = 500'000;  // 2 kHz

// The largest change of the force from one cycle to the next, and the force at the end, for a box whose face moves
// along x as 8 mm sin(2 pi 0.7 t) (an engine's physics), sent at 30 Hz with +-4 ms of jitter, against a hand 3 mm
// into the face at rest; `interpolate`: through a PoseTrack, else each update's pose held until the next.
struct Trial {
  double largest_step = 0.0, largest_force = 0.0, deepest_proxy_in_box = -1.0;
};

Trial run(bool interpolate) {
  SceneObject box;
  box.name = "box";
  box.shape.kind = ShapeKind::box;
  box.shape.half_extents = Eigen::Vector3d(0.02, 0.05, 0.05);
  box.material.stiffness_n_per_m = 2000.0;
  box.material.damping_n_s_per_m = 0.0;
  Scene scene{{box}};
  const double r = 0.005;
  auto engine_x = [](double t) { return 0.008 * std::sin(2 * std::numbers::pi * 0.7 * t); };
  // The box's face at x = centre + 0.02; the hand 3 mm into it where the box starts.
  const Eigen::Vector3d hand(0.02 + r - 0.003, 0.0, 0.0);
  GodObject proxy;
  ProxySettings settings;
  settings.radius_m = r;
  proxy.configure(settings, scene);
  proxy.reset(hand + Eigen::Vector3d(0.02, 0, 0));
  for (int k = 0; k < 40; ++k)
    proxy.update(hand + Eigen::Vector3d(0.02 * (1 - k / 40.0), 0, 0), Eigen::Vector3d::Zero());
  PoseTrack track;
  track.reset(Eigen::Isometry3d::Identity(), 0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-4e-3, 4e-3);
  double next_update = 1.0 / 30.0 + jitter(rng);
  Eigen::Vector3d held = Eigen::Vector3d::Zero();
  Trial out;
  Eigen::Vector3d last = proxy.update(hand, Eigen::Vector3d::Zero()).force;
  for (int k = 1; k < 2 * 2000 * 3; ++k) {  // 6 s
    const double t = k * 5e-4;
    if (t >= next_update) {
      const double sent = next_update;  // the engine's pose of the time it sent it
      track.publish(PoseUpdate{Eigen::Vector3d(engine_x(sent), 0, 0), Eigen::Quaterniond::Identity()});
      held = Eigen::Vector3d(engine_x(sent), 0, 0);
      next_update += 1.0 / 30.0 + jitter(rng);
    }
    const PoseTrack::Played played = track.at(k * kPeriodNs);
    scene.objects[0].pose = interpolate ? played.pose : Eigen::Isometry3d(Eigen::Translation3d(held));
    scene.objects[0].velocity = interpolate ? played.velocity : Eigen::Vector3d::Zero();
    const ProxyState& s = proxy.update(hand, Eigen::Vector3d::Zero());
    out.largest_step = std::max(out.largest_step, (s.force - last).norm());
    out.largest_force = std::max(out.largest_force, s.force.norm());
    out.deepest_proxy_in_box =
        std::max(out.deepest_proxy_in_box, -(closest_in_world(scene.objects[0], s.proxy).distance - r));
    last = s.force;
  }
  return out;
}

TEST(MovingObject, ABoxMovedAt30HzShowsNoForceStepAtItsUpdatesAndPushesTheHand) {
  const Trial smooth = run(true);
  const Trial held = run(false);
  std::printf("largest force step per cycle: interpolated %.3f N, held %.3f N; largest force %.2f N\n",
              smooth.largest_step, held.largest_step, smooth.largest_force);
  EXPECT_LT(smooth.largest_step, 0.2);
  EXPECT_GT(held.largest_step, 1.0) << "held poses step (what the test would not see if it could not fail)";
  // The box comes 8 mm towards the hand that was 3 mm in: it pushes with up to 2000 N/m x 11 mm.
  EXPECT_NEAR(smooth.largest_force, 2000 * 0.011, 2.0);
  EXPECT_LT(smooth.deepest_proxy_in_box, 1e-6) << "the proxy never inside the box";
}

TEST(MovingObject, WhenUpdatesStopTheObjectStopsAtTheLastPose) {
  PoseTrack track;
  track.reset(Eigen::Isometry3d::Identity(), 0);
  for (int u = 1; u <= 10; ++u) {
    track.publish(PoseUpdate{Eigen::Vector3d(0.001 * u, 0, 0), Eigen::Quaterniond::Identity()});
    for (int k = 0; k < 66; ++k) (void)track.at((u * 66 + k) * kPeriodNs);
  }
  const PoseTrack::Played later = track.at(5'000 * kPeriodNs);
  EXPECT_NEAR(later.pose.translation().x(), 0.010, 1e-12);
  EXPECT_EQ(later.velocity, Eigen::Vector3d::Zero());
  EXPECT_NEAR(track.interval_s(), 0.033, 0.002);
}

TEST(MovingObject, PlayingATrackBackAllocatesNothing) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "the sanitizer owns malloc";
  PoseTrack track;
  track.reset(Eigen::Isometry3d::Identity(), 0);
  track.publish(
      PoseUpdate{Eigen::Vector3d(0.01, 0, 0), Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()))});
  const std::size_t n = testing::count_allocations([&] {
    for (int k = 0; k < 1000; ++k) (void)track.at(k * kPeriodNs);
  });
  EXPECT_EQ(n, 0u);
}

}  // namespace
}  // namespace hapticd::scene
