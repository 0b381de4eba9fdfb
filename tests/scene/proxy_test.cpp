// The proxy (scene/proxy.hpp) driven directly, goal by goal at 2 kHz: a wall's stiffness, several constraints at
// once (a room's corner, a V-shaped crease), thin shells at speed, friction that sticks and then slides, textures
// on every contact, damping that never pulls, a start inside an object, and no allocation on the loop.
#include "hapticd/scene/proxy.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "hapticd/testing/allocation_guard.hpp"

namespace hapticd::scene {
namespace {

constexpr double kPeriod = 5e-4;  // 2 kHz

SceneObject plane(const std::string& name, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                  Material m = {}) {
  SceneObject o;
  o.name = name;
  o.shape.kind = ShapeKind::plane;
  o.pose.translation() = point;
  o.pose.linear() =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal.normalized()).toRotationMatrix();
  o.material = m;
  return o;
}

SceneObject box(const std::string& name, const Eigen::Vector3d& centre, const Eigen::Vector3d& size, Material m = {}) {
  SceneObject o;
  o.name = name;
  o.shape.kind = ShapeKind::box;
  o.shape.half_extents = 0.5 * size;
  o.pose.translation() = centre;
  o.material = m;
  return o;
}

Material stiff(double k, double damping = 0.0) {
  Material m;
  m.stiffness_n_per_m = k;
  m.damping_n_s_per_m = damping;
  return m;
}

struct Rig {
  Scene scene;
  GodObject proxy;
  Eigen::Vector3d goal = Eigen::Vector3d::Zero();
  explicit Rig(Scene s, double radius = 0.005, Eigen::Vector3d start = Eigen::Vector3d(0, 0, 0.02))
      : scene(std::move(s)), goal(start) {
    ProxySettings settings;
    settings.radius_m = radius;
    proxy.configure(settings, scene);
    proxy.reset(goal);
  }
  // Moves the goal to `to` in straight steps of at most `speed` x one period; the last state.
  const ProxyState& move(const Eigen::Vector3d& to, double speed = 0.1) {
    const double step = speed * kPeriod;
    const Eigen::Vector3d start = goal;
    const int steps = std::max(1, static_cast<int>(std::ceil((to - start).norm() / step)));
    const Eigen::Vector3d v = (to - start) / (steps * kPeriod);
    for (int k = 1; k <= steps; ++k) {
      goal = start + (to - start) * (static_cast<double>(k) / steps);
      proxy.update(goal, v);
    }
    return proxy.update(goal, Eigen::Vector3d::Zero());
  }
};

TEST(Proxy, AWallPushesBackWithItsStiffnessAndTheProxyRestsOnItsSurface) {
  Rig rig({{plane("floor", Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), stiff(2000))}});
  const ProxyState& free = rig.move({0.0, 0.0, 0.01});
  EXPECT_EQ(free.contact_count, 0);
  EXPECT_LT(free.force.norm(), 1e-12);
  for (double depth : {0.001, 0.005, 0.012}) {
    const ProxyState& s = rig.move({0.01, 0.0, 0.005 - depth});
    EXPECT_EQ(s.contact_count, 1);
    EXPECT_NEAR(s.proxy.z(), 0.005, 1e-6);
    EXPECT_NEAR(s.proxy.x(), 0.01, 1e-9);
    EXPECT_NEAR(s.force.z(), 2000 * depth, 2000 * 1e-6) << depth;
    EXPECT_NEAR(s.force.x(), 0.0, 1e-9);
  }
}

TEST(Proxy, InARoomsCornerThreeWallsHoldTheProxyAtOnce) {
  Rig rig({{plane("floor", {0, 0, 0}, Eigen::Vector3d::UnitZ(), stiff(1000)),
            plane("wall_x", {0, 0, 0}, Eigen::Vector3d::UnitX(), stiff(1000)),
            plane("wall_y", {0, 0, 0}, Eigen::Vector3d::UnitY(), stiff(1000))}},
          0.005, {0.03, 0.03, 0.03});
  const ProxyState& s = rig.move({-0.01, -0.02, -0.005});
  EXPECT_EQ(s.contact_count, 3);
  EXPECT_LT((s.proxy - Eigen::Vector3d(0.005, 0.005, 0.005)).norm(), 1e-6) << s.proxy.transpose();
  EXPECT_LT((s.force - 1000 * (s.proxy - rig.goal)).norm(), 1e-3);
}

TEST(Proxy, InAVShapedCreaseTheProxySitsInTheFoldWhereverTheHandPresses) {
  const Eigen::Vector3d n1 = Eigen::Vector3d(1, 0, 1).normalized(), n2 = Eigen::Vector3d(-1, 0, 1).normalized();
  const double r = 0.005;
  Rig rig({{plane("left", {0, 0, 0}, n1, stiff(1500)), plane("right", {0, 0, 0}, n2, stiff(1500))}}, r,
          {0.0, 0.0, 0.03});
  // Pressing down anywhere between the two normals' directions: the proxy ends in the fold x = 0, z = r sqrt 2.
  for (double x = -0.004; x <= 0.004; x += 0.0005) {
    const ProxyState& s = rig.move({x, 0.01, -0.02});
    EXPECT_EQ(s.contact_count, 2) << x;
    EXPECT_NEAR(s.proxy.x(), 0.0, 1e-6) << x;
    EXPECT_NEAR(s.proxy.z(), r * std::sqrt(2.0), 1e-6) << x;
    rig.move({0.0, 0.01, 0.03});
  }
}

TEST(Proxy, AOneMillimetreShellIsNotPassedAtOneOrTenMetresASecond) {
  for (double speed : {1.0, 10.0}) {
    Rig rig({{box("shell", {0, 0, 0}, {0.2, 0.2, 0.001}, stiff(3000))}}, 0.002, {0.01, 0.0, 0.03});
    double lowest = 1.0;
    const double step = speed * kPeriod;
    for (int k = 0; k < 200; ++k) {
      rig.goal.z() -= step;
      const ProxyState& s = rig.proxy.update(rig.goal, Eigen::Vector3d(0, 0, -speed));
      lowest = std::min(lowest, s.proxy.z());
    }
    EXPECT_GT(lowest, 0.0005 + 0.002 - 1e-6) << speed << " m/s: the proxy went through the shell";
    EXPECT_LT(rig.proxy.state().proxy.z(), 0.0025 + 1e-5);
  }
}

TEST(Proxy, FrictionSticksUpToTheStaticLimitThenSlidesAtTheDynamicOne) {
  Material m = stiff(2000);
  m.static_friction = 0.6;
  m.dynamic_friction = 0.4;
  const double r = 0.005, depth = 0.005;  // a 10 N normal force
  Rig rig({{plane("floor", {0, 0, 0}, Eigen::Vector3d::UnitZ(), m)}}, r, {0.0, 0.0, 0.02});
  rig.move({0.0, 0.0, r - depth}, 0.05);
  double largest = 0.0;
  std::vector<double> tangential;
  bool slid = false;
  double first_slide_x = 0.0;
  for (int k = 0; k < 2000; ++k) {  // 20 um a cycle: 4 cm/s across the floor
    rig.goal.x() += 2e-5;
    const ProxyState& s = rig.proxy.update(rig.goal, Eigen::Vector3d(0.04, 0, 0));
    EXPECT_NEAR(s.force.z(), 10.0, 1e-3);
    tangential.push_back(-s.force.x());
    largest = std::max(largest, -s.force.x());
    if (s.sliding && !slid) {
      slid = true;
      first_slide_x = rig.goal.x();
    }
  }
  EXPECT_TRUE(slid);
  EXPECT_NEAR(largest, 6.0, 2000 * 2e-5 + 1e-6) << "the static limit: 0.6 x 10 N";
  // It stuck until the hand had gone mu_s depth / ... = 3 mm (6 N / 2000 N/m) past where it landed.
  EXPECT_NEAR(first_slide_x, 0.003, 2.5e-5);
  // (The proxy rests 0.1 um off the surface - the sweep's skin - so the depth, and with it the cones, is 0.002 % more.)
  for (std::size_t k = 1000; k < tangential.size(); ++k) EXPECT_NEAR(tangential[k], 4.0, 2e-4) << k;
  // Stopped, it sticks again: the force stays at the dynamic level while the hand rests.
  for (int k = 0; k < 20; ++k) rig.proxy.update(rig.goal, Eigen::Vector3d::Zero());
  EXPECT_FALSE(rig.proxy.state().sliding);
  EXPECT_NEAR(-rig.proxy.state().force.x(), 4.0, 2e-4);
}

// The zero crossings of a signal about its mean: their mean spacing (half the period of a ripple).
double mean_half_period(const std::vector<double>& x, const std::vector<double>& f) {
  double mean = 0.0;
  for (double v : f) mean += v / static_cast<double>(f.size());
  std::vector<double> crossings;
  for (std::size_t k = 1; k < f.size(); ++k)
    if ((f[k - 1] - mean) * (f[k] - mean) < 0.0) crossings.push_back(x[k]);
  if (crossings.size() < 3) return 0.0;
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

TEST(Proxy, ATextureRipplesTheForceAtItsSpatialPeriodOnEveryContact) {
  Material m = stiff(2000);
  m.texture_amplitude_m = 2e-4;
  m.texture_period_m = 0.004;
  // A V-shaped crease of two textured planes: stroking along the fold, both contacts ripple.
  const Eigen::Vector3d n1 = Eigen::Vector3d(1, 0, 1).normalized(), n2 = Eigen::Vector3d(-1, 0, 1).normalized();
  Rig rig({{plane("left", {0, 0, 0}, n1, m), plane("right", {0, 0, 0}, n2, m)}}, 0.003, {0.0, 0.0, 0.03});
  rig.move({0.0, 0.0, -0.002});
  std::vector<double> y, left, right;
  for (int k = 0; k < 4000; ++k) {
    rig.goal.y() += 1e-5;
    const ProxyState& s = rig.proxy.update(rig.goal, Eigen::Vector3d(0, 0.02, 0));
    ASSERT_EQ(s.contact_count, 2);
    y.push_back(rig.goal.y());
    left.push_back(s.contacts[0].force.dot(s.contacts[0].normal));
    right.push_back(s.contacts[1].force.dot(s.contacts[1].normal));
  }
  EXPECT_NEAR(2.0 * mean_half_period(y, left), 0.004, 0.0001);
  EXPECT_NEAR(2.0 * mean_half_period(y, right), 0.004, 0.0001);
  const auto [lo, hi] = std::minmax_element(left.begin(), left.end());
  EXPECT_GT(*hi - *lo, 2000 * 2e-4 * 0.5);  // the ripple is there, of the relief's size
}

TEST(Proxy, DampingActsOnlyWhileTheHandMovesIntoTheSurfaceAndTheSurfaceNeverPulls) {
  Rig rig({{plane("floor", {0, 0, 0}, Eigen::Vector3d::UnitZ(), stiff(2000, 50))}});
  rig.move({0, 0, 0.004});  // the proxy's surface touches at z = 0.005: 1 mm deep
  const ProxyState& in = rig.proxy.update(rig.goal, Eigen::Vector3d(0, 0, -0.1));
  EXPECT_NEAR(in.force.z(), 2.0 + 5.0, 3e-4);  // (the proxy rests 0.1 um off: the sweep's skin)
  const ProxyState& out = rig.proxy.update(rig.goal, Eigen::Vector3d(0, 0, 0.5));
  EXPECT_NEAR(out.force.z(), 2.0, 3e-4) << "damping on the way out would pull";
}

TEST(Proxy, AnObjectThatHoldsTheHandAtTheStartIsLeftOutUntilTheHandLeavesIt) {
  Rig rig({{box("block", {0, 0, 0}, {0.04, 0.04, 0.04}, stiff(2000))}}, 0.005, {0.0, 0.0, 0.0});
  EXPECT_LT(rig.proxy.update(rig.goal, Eigen::Vector3d::Zero()).force.norm(), 1e-12) << "no kick at the start";
  rig.move({0.0, 0.0, 0.05});
  EXPECT_LT(rig.proxy.state().force.norm(), 1e-12);
  const ProxyState& s = rig.move({0.0, 0.0, 0.02});  // back onto the top: felt now
  EXPECT_NEAR(s.force.z(), 2000 * 0.005, 3e-4);
}

TEST(Proxy, StrokingASphereTheForceIsAlongItsNormal) {
  SceneObject ball;
  ball.name = "ball";
  ball.shape.kind = ShapeKind::sphere;
  ball.shape.radius = 0.04;
  ball.material = stiff(1500);
  Rig rig({{ball}}, 0.005, {0.0, 0.0, 0.08});
  double worst = 0.0;
  for (int k = 0; k <= 400; ++k) {
    const double a = std::numbers::pi / 2 * (1.0 - k / 400.0);  // from the top down the side, 3 mm deep
    rig.move({(0.045 - 0.003) * std::cos(a), 0.0, (0.045 - 0.003) * std::sin(a)}, 0.2);
    const ProxyState& s = rig.proxy.state();
    const Eigen::Vector3d normal = rig.goal.normalized();
    worst = std::max(worst, std::acos(std::min(1.0, s.force.normalized().dot(normal))));
    EXPECT_NEAR(s.force.norm(), 1500 * 0.003, 1500 * 2e-6);
  }
  EXPECT_LT(worst * 180 / std::numbers::pi, 0.01);
}

TEST(Proxy, UpdateAllocatesNothing) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "the sanitizer owns malloc";
  Material m = stiff(2000, 10);
  m.static_friction = 0.5;
  m.dynamic_friction = 0.3;
  m.texture_amplitude_m = 1e-4;
  Rig rig({{plane("floor", {0, 0, 0}, Eigen::Vector3d::UnitZ(), m), box("b", {0.02, 0, 0}, {0.01, 0.01, 0.01}, m)}});
  rig.move({0.0, 0.0, 0.002});
  const std::size_t n = testing::count_allocations([&] {
    for (int k = 0; k < 500; ++k)
      rig.proxy.update(rig.goal + Eigen::Vector3d(4e-5 * k, 0, -1e-5 * k), {0.08, 0, -0.02});
  });
  EXPECT_EQ(n, 0u);
}

}  // namespace
}  // namespace hapticd::scene
