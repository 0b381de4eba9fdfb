// Collision geometry: closest points of segments against a dense sampling, capsule clearances, capsules from the
// URDF's <collision> elements and along the skeleton, placed with the model (mounted or not).
#include "hapticd/model/collision.hpp"

#include <gtest/gtest.h>

#include <random>

#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/urdf_loader.hpp"
#include "support/device_models.hpp"

namespace hapticd {
namespace {

using Eigen::Vector3d;

// The distance of two segments by sampling both densely and refining around the best sample pair.
double sampled_distance(const Vector3d& p0, const Vector3d& p1, const Vector3d& q0, const Vector3d& q1) {
  double best = 1e9;
  constexpr int kSteps = 400;
  for (int i = 0; i <= kSteps; ++i) {
    const Vector3d p = p0 + (p1 - p0) * (static_cast<double>(i) / kSteps);
    // For a fixed point the closest point of a segment is exact: clamp the projection.
    const Vector3d d = q1 - q0;
    const double t = d.squaredNorm() > 0 ? std::clamp((p - q0).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (p - (q0 + t * d)).norm());
  }
  return best;
}

TEST(Collision, ClosestPointsOfSegmentsMatchASampledSearch) {
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto point = [&] { return Vector3d(u(rng), u(rng), u(rng)); };
  for (int k = 0; k < 500; ++k) {
    Vector3d p0 = point(), p1 = point(), q0 = point(), q1 = point();
    if (k % 5 == 1) q1 = q0 + 0.3 * (p1 - p0);  // parallel
    if (k % 5 == 2) p1 = p0;                    // a point
    if (k % 5 == 3) q1 = q0;
    const model::SegmentPair s = model::closest_points(p0, p1, q0, q1);
    // Sampling only finds an upper bound, close to the truth: the exact answer is never above it.
    const double sampled = sampled_distance(p0, p1, q0, q1);
    EXPECT_LE(s.distance, sampled + 1e-12) << "case " << k;
    EXPECT_NEAR(s.distance, sampled, 5e-3) << "case " << k;
    EXPECT_NEAR((s.on_p - s.on_q).norm(), s.distance, 1e-12);
  }
}

TEST(Collision, ClearanceOfCapsulesIsBetweenTheirSurfaces) {
  model::PlacedCapsules a, b;
  a.count = 2;
  a.a[0] = Vector3d(0, 0, 0), a.b[0] = Vector3d(1, 0, 0), a.radius[0] = 0.1;
  a.a[1] = Vector3d(5, 5, 5), a.b[1] = Vector3d(6, 5, 5), a.radius[1] = 0.1;
  b.count = 1;
  b.a[0] = Vector3d(0.5, 1.0, -1), b.b[0] = Vector3d(0.5, 1.0, 1), b.radius[0] = 0.2;  // crosses 1 m above x
  const model::Clearance c = model::nearest(a, b);
  EXPECT_NEAR(c.distance, 1.0 - 0.1 - 0.2, 1e-12);
  EXPECT_EQ(c.capsule_first, 0);
  EXPECT_EQ(c.capsule_second, 0);
  EXPECT_TRUE(c.point_first.isApprox(Vector3d(0.5, 0.1, 0.0), 1e-12));
  EXPECT_TRUE(c.point_second.isApprox(Vector3d(0.5, 0.8, 0.0), 1e-12));
  b.radius[0] = 1.5;  // overlapping: negative clearance
  EXPECT_NEAR(model::nearest(a, b).distance, -0.6, 1e-12);
  b.count = 0;
  EXPECT_GT(model::nearest(a, b).distance, 1e8);
}

constexpr const char* kTwoLinks = R"(<robot name="two">
  <link name="base"><collision><origin xyz="0 0 0.05"/><geometry><box size="0.2 0.1 0.1"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <link name="l1">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0.25 0 0" rpy="0 1.5707963267948966 0"/><geometry><cylinder radius="0.03" length="0.5"/></geometry></collision>
    <collision><origin xyz="0.5 0 0"/><geometry><sphere radius="0.04"/></geometry></collision>
  </link>
</robot>)";

TEST(Collision, CapsulesComeFromTheUrdfsCollisionElements) {
  const model::RobotModel m = model::parse_robot_model(kTwoLinks, "two.urdf");
  ASSERT_EQ(m.collision().size(), 3u);
  const model::Capsule& box = m.collision()[0];
  EXPECT_EQ(box.link, "base");
  EXPECT_EQ(box.body, -1);
  EXPECT_TRUE(box.a.isApprox(Vector3d(-0.1, 0, 0.05)));  // along the box's longest side
  EXPECT_TRUE(box.b.isApprox(Vector3d(0.1, 0, 0.05)));
  EXPECT_NEAR(box.radius, std::sqrt(0.1 * 0.1 + 0.1 * 0.1) / 2, 1e-12);
  const model::Capsule& cylinder = m.collision()[1];
  EXPECT_EQ(cylinder.body, 0);
  EXPECT_LT((cylinder.a - Vector3d(0, 0, 0)).norm() + (cylinder.b - Vector3d(0.5, 0, 0)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(cylinder.radius, 0.03);
  EXPECT_TRUE(m.collision()[2].a.isApprox(m.collision()[2].b));

  // Placed: turned a quarter about z, the cylinder points along y; mounted 1 m up, everything is 1 m higher.
  const model::RobotModel mounted = m.with_base(Eigen::Isometry3d(Eigen::Translation3d(0, 0, 1)));
  model::ModelData data(mounted);
  JointVector q(1);
  q[0] = 1.5707963267948966;
  model::forward_kinematics(mounted, data, q);
  model::PlacedCapsules placed;
  model::place_capsules(mounted, data, placed);
  ASSERT_EQ(placed.count, 3);
  EXPECT_TRUE(placed.a[0].isApprox(Vector3d(-0.1, 0, 1.05)));
  EXPECT_LT((placed.b[1] - Vector3d(0, 0.5, 1.1)).norm(), 1e-12);

  const std::string mesh = std::string(kTwoLinks).replace(std::string(kTwoLinks).find("<sphere radius=\"0.04\"/>"), 23,
                                                          "<mesh filename=\"l1.stl\"/>");
  try {
    (void)model::parse_robot_model(mesh, "two.urdf");
    FAIL() << "a mesh must be refused";
  } catch (const model::ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("link 'l1'"), std::string::npos) << e.what();
  }
}

TEST(Collision, TheSkeletonCoversEveryLinkFromJointToJoint) {
  for (const char* name : test::kDeviceModels) {
    const model::RobotModel m = test::load_device_model(name);
    const std::vector<model::Capsule> capsules = model::skeleton_capsules(m, 0.03);
    ASSERT_LE(capsules.size(), static_cast<std::size_t>(model::PlacedCapsules::kMax)) << name;
    for (int i = 0; i < m.dof(); ++i) {
      bool covered = false;
      for (const auto& c : capsules) covered = covered || c.body == i;
      EXPECT_TRUE(covered) << name << " body " << i;
    }
    // At any posture, each joint's origin lies on a capsule of its parent and the handle on one of its body.
    const model::RobotModel with = m.with_collision(capsules);
    model::ModelData data(with);
    std::mt19937_64 rng(3);
    const JointVector q = test::random_joint_vector(rng, m.dof(), 1.0);
    model::forward_kinematics(with, data, q);
    model::PlacedCapsules placed;
    model::place_capsules(with, data, placed);
    const Vector3d handle = model::frame_pose(with, data, with.require_frame("handle")).translation();
    double nearest_end = 1e9;
    for (int k = 0; k < placed.count; ++k)
      nearest_end = std::min(nearest_end, (placed.b[static_cast<std::size_t>(k)] - handle).norm());
    EXPECT_LT(nearest_end, 1e-9) << name;
  }
}

TEST(Collision, TheClearanceGradientIsTheClearancesDerivative) {
  // Two ViSHaRD10s (every joint moves its links) side by side; the clearance between them against central
  // differences of the clearance itself, joint by joint, for both arms (each with its own point and normal).
  const model::RobotModel base = test::load_device_model("vishard10");
  const model::RobotModel m = base.with_collision(model::skeleton_capsules(base, 0.03));
  const model::RobotModel first = m.with_base(Eigen::Isometry3d(Eigen::Translation3d(0, 0.25, 0)));
  const model::RobotModel second = m.with_base(Eigen::Isometry3d(Eigen::Translation3d(0, -0.25, 0)));
  model::ModelData da(first), db(second);
  std::mt19937_64 rng(11);
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const JointVector qa = test::random_joint_vector(rng, m.dof(), 1.5);
    const JointVector qb = test::random_joint_vector(rng, m.dof(), 1.5);
    const auto clearance = [&](const JointVector& a, const JointVector& b) {
      model::PlacedCapsules pa, pb;
      model::forward_kinematics(first, da, a);
      model::forward_kinematics(second, db, b);
      model::place_capsules(first, da, pa);
      model::place_capsules(second, db, pb);
      return model::nearest(pa, pb);
    };
    const model::Clearance c = clearance(qa, qb);
    if (c.distance < 0.0) continue;  // overlapping: the nearest pair is not where the gradient applies
    JointVector ga, gb;
    model::forward_kinematics(first, da, qa);
    model::clearance_gradient(first, da, first.collision()[static_cast<std::size_t>(c.capsule_first)].body,
                              c.point_first, c.normal, ga);
    model::forward_kinematics(second, db, qb);
    model::clearance_gradient(second, db, second.collision()[static_cast<std::size_t>(c.capsule_second)].body,
                              c.point_second, -c.normal, gb);
    ASSERT_EQ(ga.size(), m.dof());
    constexpr double h = 1e-6;
    for (int j = 0; j < m.dof(); ++j) {
      JointVector up = qa, down = qa;
      up[j] += h;
      down[j] -= h;
      const model::Clearance cu = clearance(up, qb), cd = clearance(down, qb);
      if (cu.capsule_first != c.capsule_first || cd.capsule_first != c.capsule_first) continue;  // a switch
      EXPECT_NEAR(ga[j], (cu.distance - cd.distance) / (2 * h), 1e-5) << "first arm, joint " << j + 1;
      up = qb;
      down = qb;
      up[j] += h;
      down[j] -= h;
      const model::Clearance su = clearance(qa, up), sd = clearance(qa, down);
      if (su.capsule_second != c.capsule_second || sd.capsule_second != c.capsule_second) continue;
      EXPECT_NEAR(gb[j], (su.distance - sd.distance) / (2 * h), 1e-5) << "second arm, joint " << j + 1;
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
}

TEST(Collision, ModelsRefuseBadCapsules) {
  const model::RobotModel m = model::parse_robot_model(kTwoLinks, "two.urdf");
  EXPECT_THROW((void)m.with_collision({model::Capsule{"x", 3, Vector3d::Zero(), Vector3d::Zero(), 0.1}}),
               std::invalid_argument);
  EXPECT_THROW((void)m.with_collision({model::Capsule{"x", 0, Vector3d::Zero(), Vector3d::Zero(), -0.1}}),
               std::invalid_argument);
  EXPECT_THROW((void)m.with_collision(std::vector<model::Capsule>(model::PlacedCapsules::kMax + 1)),
               std::invalid_argument);
}

}  // namespace
}  // namespace hapticd
