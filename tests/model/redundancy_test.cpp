// The redundancy toolbox (hapticd/model/redundancy.hpp, side_criteria.hpp) on the ViSHaRD10 model (10 joints,
// 6-D task) at random configurations: the properties of [U06] methods 3 that hold whatever the
// configuration.
#include "hapticd/model/redundancy.hpp"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <numbers>
#include <vector>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/side_criteria.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "support/device_models.hpp"

namespace hapticd {
namespace {

using model::GeneralizedInverse;
using model::InverseKind;
using model::TaskJacobian;
using model::TaskVector;

constexpr InverseKind kKinds[] = {InverseKind::pseudoinverse, InverseKind::weighted, InverseKind::damped,
                                  InverseKind::inertia_weighted};

class Redundancy : public ::testing::Test {
 protected:
  void SetUp() override {
    robot_ = std::make_unique<model::RobotModel>(test::load_device_model("vishard10"));
    handle_ = robot_->require_frame("handle");
    data_ = std::make_unique<model::ModelData>(*robot_);
    weights_.resize(10);
    weights_ << 1.0, 1.0, 1.0, 1.0, 3.0, 1.0, 1.0, 0.2, 1.0, 0.1;  // the thesis's wrist weights on 5, 8, 9, 10
  }
  // Kinematics and inertia at q; the 6 x 10 Jacobian in jacobian_.
  void at(const JointVector& q) {
    model::forward_kinematics(*robot_, *data_, q);
    model::frame_jacobian(*robot_, *data_, handle_, jacobian_);
    model::joint_space_inertia(*robot_, *data_);
  }
  JointVector random_q() {
    JointVector q = test::random_joint_vector(rng_, 10, std::numbers::pi);
    q[8] = 0.4 + std::fmod(std::abs(q[8]), 2.3);  // joint 9 away from its singular values 0, pi
    return q;
  }
  GeneralizedInverse inverse(InverseKind kind, double damping = 0.02) {
    GeneralizedInverse g;
    g.configure(kind, 10, weights_, damping);
    g.compute(jacobian_, &data_->mass_llt);
    return g;
  }
  Eigen::Isometry3d pose_at(const JointVector& q) {
    model::forward_kinematics(*robot_, *data_, q);
    return model::frame_pose(*robot_, *data_, handle_);
  }

  std::unique_ptr<model::RobotModel> robot_;
  std::unique_ptr<model::ModelData> data_;
  int handle_ = -1;
  JointVector weights_;
  TaskJacobian jacobian_;
  std::mt19937_64 rng_{8};
};

TEST_F(Redundancy, ExactInversesSolveJqdEqualsXd) {
  // pseudoinverse, weighted and inertia-weighted: J J^W# = I (full row rank). The damped inverse is not exact:
  // along a singular direction of J with singular value s it delivers s^2 / (s^2 + lambda^2) of the motion, so
  // its relative error is at most lambda^2 / (s_min^2 + lambda^2) (weights 1 here).
  constexpr double kLambda = 0.02;
  double worst_exact = 0.0, worst_damped_share = 0.0;
  for (int k = 0; k < 100; ++k) {
    at(random_q());
    const Eigen::JacobiSVD<TaskJacobian> svd(jacobian_);
    const double s = svd.singularValues()[5];
    const TaskVector xd = TaskVector::Random(6);
    for (InverseKind kind : kKinds) {
      if (kind == InverseKind::damped) {
        GeneralizedInverse g;
        g.configure(kind, 10, JointVector::Ones(10), kLambda);
        g.compute(jacobian_);
        const double error = (jacobian_ * g.solve(xd) - xd).norm() / xd.norm();
        const double bound = kLambda * kLambda / (s * s + kLambda * kLambda);
        EXPECT_LE(error, bound + 1e-12);
        worst_damped_share = std::max(worst_damped_share, error / bound);
      } else {
        worst_exact = std::max(worst_exact, (jacobian_ * inverse(kind).solve(xd) - xd).norm() / xd.norm());
      }
    }
  }
  std::printf(
      "J qd = xd: worst relative error %.2e (exact inverses); damped: up to %.0f %% of its bound "
      "lambda^2 / (s_min^2 + lambda^2)\n",
      worst_exact, 100.0 * worst_damped_share);
  EXPECT_LT(worst_exact, 1e-10);
  EXPECT_GT(worst_damped_share, 0.01);  // the damping is there
}

TEST_F(Redundancy, WeightedInversesMinimiseTheirWeightedNorm) {
  // Among all solutions qd + N z, J^W# xd has the smallest qd^T W qd (W = diag(w), or M).
  for (int k = 0; k < 20; ++k) {
    at(random_q());
    const TaskVector xd = TaskVector::Random(6);
    for (InverseKind kind : {InverseKind::pseudoinverse, InverseKind::weighted, InverseKind::inertia_weighted}) {
      const GeneralizedInverse g = inverse(kind);
      const JointMatrix w = kind == InverseKind::inertia_weighted ? data_->mass_matrix
                            : kind == InverseKind::weighted       ? JointMatrix(weights_.asDiagonal())
                                                                  : JointMatrix(JointMatrix::Identity(10, 10));
      const JointVector best = g.solve(xd);
      const double cost = best.dot(w * best);
      for (int t = 0; t < 20; ++t) {
        const JointVector other = best + g.null_space_projector() * JointVector(JointVector::Random(10));
        EXPECT_NEAR((jacobian_ * other - xd).norm(), 0.0, 1e-9);
        EXPECT_GE(other.dot(w * other), cost - 1e-9) << to_string(kind);
      }
    }
  }
}

TEST_F(Redundancy, NullSpaceMotionLeavesTheHandleStill) {
  // Instantaneously J N = 0 for every inverse; integrated, a self-motion of 0.5 rad along the null space moves
  // the handle by second-order terms only.
  double worst = 0.0;
  for (int k = 0; k < 50; ++k) {
    at(random_q());
    for (InverseKind kind : kKinds) {
      if (kind == InverseKind::damped) continue;  // its N is not an exact projector
      worst = std::max(worst, (jacobian_ * inverse(kind).null_space_projector()).norm());
    }
  }
  EXPECT_LT(worst, 1e-10);
  JointVector q = random_q();
  const Eigen::Isometry3d start = pose_at(q);
  JointVector direction = JointVector::Zero(10);
  direction[8] = 1.0;  // push joint 9; the null space carries the rest along
  double travelled = 0.0;
  for (int step = 0; step < 5000; ++step) {
    at(q);
    const JointVector qd = inverse(InverseKind::pseudoinverse).null_space_projector() * direction;
    q += 1e-4 * qd / std::max(qd.norm(), 1e-12);
    travelled += 1e-4;
  }
  const model::Vector6d moved = model::pose_difference(pose_at(q), start);
  std::printf("self-motion of %.2f rad (joint space): handle moved %.2e m, %.2e rad\n", travelled,
              moved.head<3>().norm(), moved.tail<3>().norm());
  EXPECT_LT(moved.head<3>().norm(), 1e-4);
  EXPECT_LT(moved.tail<3>().norm(), 1e-4);
}

TEST_F(Redundancy, TheInertiaWeightedInverseMakesNoNullSpaceAccelerationFromAHandleWrench) {
  // A wrench F at the handle accelerates the joints by qdd = M^-1 J^T F. Its null-space part (I - J^M# J) qdd
  // is zero for the dynamically consistent inverse, not for the plain pseudoinverse.
  double consistent = 0.0, plain = 0.0;
  for (int k = 0; k < 50; ++k) {
    at(random_q());
    const TaskVector f = TaskVector::Random(6) * 10.0;
    const JointVector qdd = data_->mass_llt.solve(JointVector(jacobian_.transpose() * f));
    consistent =
        std::max(consistent, (inverse(InverseKind::inertia_weighted).null_space_projector() * qdd).norm() / qdd.norm());
    plain = std::max(plain, (inverse(InverseKind::pseudoinverse).null_space_projector() * qdd).norm() / qdd.norm());
  }
  std::printf("null-space share of the acceleration from a handle wrench: %.2e inertia-weighted, %.2f pseudoinverse\n",
              consistent, plain);
  EXPECT_LT(consistent, 1e-9);
  EXPECT_GT(plain, 0.1);
}

TEST_F(Redundancy, NullSpaceTorquesMakeNoTaskAcceleration) {
  // Torque level: J M^-1 (I - J^T J^M#T) tau0 = 0 for any tau0.
  double worst = 0.0;
  for (int k = 0; k < 50; ++k) {
    at(random_q());
    const JointVector tau0 = JointVector::Random(10) * 20.0;
    const JointVector tau = model::null_space_torque(inverse(InverseKind::inertia_weighted), jacobian_, tau0);
    worst = std::max(worst, (jacobian_ * data_->mass_llt.solve(tau)).norm() / tau0.norm());
  }
  EXPECT_LT(worst, 1e-10);
}

TEST_F(Redundancy, AccelerationLevelResolutionReproducesTheTaskAcceleration) {
  for (int k = 0; k < 50; ++k) {
    const JointVector q = random_q();
    const JointVector qd = JointVector::Random(10);
    model::forward_velocity(*robot_, *data_, q, qd);
    model::frame_jacobian(*robot_, *data_, handle_, jacobian_);
    model::joint_space_inertia(*robot_, *data_);
    const model::Vector6d bias = model::frame_jacobian_dot_times_qd(*robot_, *data_, handle_);
    const TaskVector xdd = TaskVector::Random(6);
    const JointVector qdd0 = JointVector::Random(10);  // any null-space acceleration
    for (InverseKind kind : {InverseKind::pseudoinverse, InverseKind::weighted, InverseKind::inertia_weighted}) {
      const JointVector qdd = model::resolve_acceleration(inverse(kind), TaskVector(xdd - bias), qdd0);
      EXPECT_LT((jacobian_ * qdd + bias - xdd).norm(), 1e-9);
    }
  }
}

TEST_F(Redundancy, TheDampedInverseBoundsJointRatesNearASingularity) {
  // A Jacobian of the model with its smallest singular value pushed to 1e-5 (as at a singular configuration):
  // the pseudoinverse answers a motion along the lost direction with joint rates of the order 1/1e-5, the
  // damped inverse with at most 1/(2 lambda) times the task rate.
  at(random_q());
  Eigen::JacobiSVD<TaskJacobian> svd(jacobian_, Eigen::ComputeThinU | Eigen::ComputeThinV);
  TaskVector sigma = svd.singularValues();
  sigma[5] = 1e-5;
  const TaskJacobian near = svd.matrixU() * sigma.asDiagonal() * svd.matrixV().transpose();
  const TaskVector xd = 0.1 * svd.matrixU().col(5);  // 0.1 (m/s, rad/s) along the lost direction
  GeneralizedInverse plain, damped;
  plain.configure(InverseKind::pseudoinverse, 10, JointVector::Ones(10));
  damped.configure(InverseKind::damped, 10, JointVector::Ones(10), 0.05);
  plain.compute(near);
  damped.compute(near);
  const double plain_rate = plain.solve(xd).norm(), damped_rate = damped.solve(xd).norm();
  std::printf(
      "0.1 along the lost direction (s_min 1e-5): joint rate %.0f rad/s (pseudoinverse), %.3f rad/s (damped, "
      "lambda 0.05)\n",
      plain_rate, damped_rate);
  EXPECT_GT(plain_rate, 1000.0);
  EXPECT_LE(damped_rate, 0.1 / (2.0 * 0.05) + 1e-12);
}

TEST_F(Redundancy, ExactInversesDropTheLostDirectionOfARankDeficientJacobian) {
  // Two equal rows: rank 5, the Gram matrix singular, so the exact kinds take the eigen-decomposition fallback.
  // The result must still be a generalised inverse (J J# J = J, J# J J# = J#), finite, and computed without
  // allocating.
  at(random_q());
  TaskJacobian deficient = jacobian_;
  deficient.row(5) = deficient.row(4);
  for (InverseKind kind : {InverseKind::pseudoinverse, InverseKind::weighted, InverseKind::inertia_weighted}) {
    GeneralizedInverse g;
    g.configure(kind, 10, weights_);
    std::size_t allocations = 0;
    if (testing::AllocationGuard::available()) {
      allocations = testing::count_allocations([&] { g.compute(deficient, &data_->mass_llt); });
    } else {
      g.compute(deficient, &data_->mass_llt);
    }
    EXPECT_EQ(allocations, 0u) << to_string(kind);
    EXPECT_EQ(g.rank(), 5) << to_string(kind);
    ASSERT_TRUE(g.matrix().allFinite()) << to_string(kind);
    EXPECT_LT((deficient * g.matrix() * deficient - deficient).norm() / deficient.norm(), 1e-9) << to_string(kind);
    EXPECT_LT((g.matrix() * deficient * g.matrix() - g.matrix()).norm() / g.matrix().norm(), 1e-9) << to_string(kind);
  }
}

TEST_F(Redundancy, SideCriteriaGradientsMatchFiniteDifferences) {
  // The analytic gradients (the singular values' through the Jacobian's derivative, the keep-out distance's
  // through the frame Jacobian) against central differences of the criteria's values, for the full task and the
  // translation rows, each Jacobian criterion alone and all together.
  model::SideCriteriaSettings all;
  all.frame = handle_;
  all.manipulability = 1.0;
  all.condition_number = 0.01;
  all.smallest_singular_value = 0.5;
  all.wrist = 2.0;
  all.keep_out = 1.0;
  all.keep_out_center = Eigen::Vector3d(0.8, 0.0, 0.5);
  all.keep_out_radius_m = 0.3;
  all.keep_out_margin_m = 2.0;  // always inside the margin: the term is smooth here
  std::vector<model::SideCriteriaSettings> cases;
  for (int rows : {6, 3}) {
    model::SideCriteriaSettings s = all;
    s.task_rows = rows;
    cases.push_back(s);
    for (int alone = 0; alone < 3; ++alone) {
      model::SideCriteriaSettings one;
      one.frame = handle_;
      one.task_rows = rows;
      (alone == 0 ? one.manipulability : alone == 1 ? one.condition_number : one.smallest_singular_value) = 1.0;
      cases.push_back(one);
    }
  }
  double worst = 0.0;
  for (const model::SideCriteriaSettings& s : cases) {
    model::SideCriteria c;
    c.configure(*robot_, s);
    for (int k = 0; k < 10; ++k) {
      const JointVector q = random_q();
      JointVector gradient;
      const double h = c.evaluate(q, gradient);
      for (int i = 0; i < 10; ++i) {
        JointVector a = q, b = q;
        a[i] += 1e-5;
        b[i] -= 1e-5;
        const double central = (c.value(a) - c.value(b)) / 2e-5;
        const double error = std::abs(gradient[i] - central) / (1.0 + std::abs(central));
        worst = std::max(worst, error);
        EXPECT_LT(error, 1e-6) << "joint " << i + 1 << ", " << s.task_rows << " rows";
      }
      EXPECT_NEAR(h, c.value(q), 1e-12);
    }
  }
  std::printf("side-criteria gradients against central differences: worst relative error %.1e\n", worst);
}

TEST_F(Redundancy, ComputingTheInversesAndCriteriaDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  model::SideCriteriaSettings s;
  s.frame = handle_;
  s.manipulability = 1.0;
  s.condition_number = 1.0;
  s.wrist = 1.0;
  s.keep_out = 1.0;
  model::SideCriteria c;
  c.configure(*robot_, s);
  GeneralizedInverse g[4];
  for (int k = 0; k < 4; ++k) g[k].configure(kKinds[k], 10, weights_, 0.02);
  const JointVector q = random_q();
  JointVector gradient(10);
  const std::size_t allocations = testing::count_allocations([&] {
    at(q);
    for (auto& inv : g) {
      inv.compute(jacobian_, &data_->mass_llt);
      const JointVector qd = model::resolve_velocity(inv, TaskVector::Ones(6), JointVector::Ones(10));
      (void)qd;
    }
    (void)c.evaluate(q, gradient);
    (void)model::null_space_torque(g[3], jacobian_, JointVector::Ones(10));
  });
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace hapticd
