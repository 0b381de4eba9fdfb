// Properties of the model algorithms that hold whatever the reference: Jacobians and dJ/dt qd against finite
// differences, M symmetric positive definite, dM/dt - 2C skew-symmetric, energy conserved in free motion,
// inverse and forward dynamics consistent, and the structural facts of the ViSHaRD devices.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <numbers>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/task_space.hpp"
#include "support/device_models.hpp"

namespace hapticd {
namespace {

using model::ModelData;
using model::RobotModel;
using model::TaskJacobian;
using model::Vector6d;

constexpr int kStates = 200;
constexpr double kPi = std::numbers::pi;

class ModelProperties : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    robot_ = std::make_unique<RobotModel>(test::load_device_model(GetParam()));
    handle_ = robot_->require_frame("handle");
    data_ = std::make_unique<ModelData>(*robot_);
  }
  Eigen::Isometry3d pose_at(const JointVector& q) {
    model::forward_kinematics(*robot_, *data_, q);
    return model::frame_pose(*robot_, *data_, handle_);
  }
  JointMatrix mass_at(const JointVector& q) {
    model::forward_kinematics(*robot_, *data_, q);
    model::joint_space_inertia(*robot_, *data_);
    return data_->mass_matrix;
  }
  int n() const { return robot_->dof(); }

  std::unique_ptr<RobotModel> robot_;
  std::unique_ptr<ModelData> data_;
  int handle_ = -1;
  std::mt19937_64 rng_{42};
};

// A device mounted elsewhere in the world (turned, tilted and hung upside down): its poses are the mounted
// ones, its Jacobian turns with the base, and gravity acts as the base sees it.
TEST_P(ModelProperties, AMountedModelComputesInTheWorldFrame) {
  const Eigen::Isometry3d base = Eigen::Translation3d(0.4, -0.3, 1.2) *
                                 Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()) *
                                 Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ());
  const RobotModel mounted = robot_->with_base(base);
  // The same arm at the origin, with gravity as the mounted base feels it.
  const RobotModel reference = robot_->with_gravity(base.linear().transpose() * robot_->gravity());
  ModelData m(mounted), r(reference);
  double largest_gravity = 0.0;
  for (int k = 0; k < 20; ++k) {
    const JointVector q = test::random_joint_vector(rng_, n(), kPi);
    model::forward_kinematics(mounted, m, q);
    model::forward_kinematics(reference, r, q);
    const Eigen::Isometry3d expected = base * model::frame_pose(reference, r, handle_);
    EXPECT_LT((model::frame_pose(mounted, m, handle_).matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-12);
    TaskJacobian jm, jr;
    model::frame_jacobian(mounted, m, handle_, jm);
    model::frame_jacobian(reference, r, handle_, jr);
    TaskJacobian turned(6, n());
    turned.topRows<3>().noalias() = base.linear() * jr.topRows<3>();
    turned.bottomRows<3>().noalias() = base.linear() * jr.bottomRows<3>();
    EXPECT_LT((jm - turned).cwiseAbs().maxCoeff(), 1e-12);
    model::gravity_torques(mounted, m);
    model::gravity_torques(reference, r);
    EXPECT_LT((m.gravity_torque - r.gravity_torque).cwiseAbs().maxCoeff(), 1e-9);
    largest_gravity = std::max(largest_gravity, r.gravity_torque.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(largest_gravity, 0.1);  // gravity does act on the arm
}

TEST_P(ModelProperties, JacobianMatchesFiniteDifferences) {
  const double h = 1e-6;
  for (int k = 0; k < kStates; ++k) {
    const JointVector q = test::random_joint_vector(rng_, n(), kPi);
    model::forward_kinematics(*robot_, *data_, q);
    TaskJacobian j;
    model::frame_jacobian(*robot_, *data_, handle_, j);
    for (int c = 0; c < n(); ++c) {
      JointVector qp = q, qm = q;
      qp[c] += h;
      qm[c] -= h;
      const Vector6d fd = model::pose_difference(pose_at(qp), pose_at(qm)) / (2 * h);
      ASSERT_LE((j.col(c) - fd).norm(), 1e-7) << "column " << c << " state " << k;
    }
  }
}

TEST_P(ModelProperties, JacobianDotTimesVelocityMatchesFiniteDifferences) {
  const double h = 1e-6;
  for (int k = 0; k < kStates; ++k) {
    const JointVector q = test::random_joint_vector(rng_, n(), kPi);
    const JointVector qd = test::random_joint_vector(rng_, n(), 2.0);
    model::forward_velocity(*robot_, *data_, q, qd);
    const Vector6d jdqd = model::frame_jacobian_dot_times_qd(*robot_, *data_, handle_);
    // d/dt (J(q + t qd) qd) at t = 0: the classical acceleration with qdd = 0.
    TaskJacobian jp, jm;
    model::forward_kinematics(*robot_, *data_, q + h * qd);
    model::frame_jacobian(*robot_, *data_, handle_, jp);
    model::forward_kinematics(*robot_, *data_, q - h * qd);
    model::frame_jacobian(*robot_, *data_, handle_, jm);
    const Vector6d fd = (jp * qd - jm * qd) / (2 * h);
    ASSERT_LE((jdqd - fd).norm(), 1e-6 * (1 + fd.norm())) << "state " << k;
  }
}

TEST_P(ModelProperties, AnalyticJacobianMatchesRollPitchYawRates) {
  const double h = 1e-6;
  int checked = 0;
  for (int k = 0; k < kStates; ++k) {
    const JointVector q = test::random_joint_vector(rng_, n(), kPi);
    const JointVector qd = test::random_joint_vector(rng_, n(), 1.0);
    model::forward_kinematics(*robot_, *data_, q);
    TaskJacobian j, ja;
    model::frame_jacobian(*robot_, *data_, handle_, j);
    if (!model::analytic_jacobian(j, data_->rotation[n() - 1] * robot_->frame(handle_).placement.linear(), ja, 0.1)) {
      continue;  // near the representation singularity
    }
    const Eigen::Vector3d rp = model::roll_pitch_yaw(pose_at(q + h * qd).linear());
    const Eigen::Vector3d rm = model::roll_pitch_yaw(pose_at(q - h * qd).linear());
    Eigen::Vector3d rate = rp - rm;
    for (int a = 0; a < 3; ++a) rate[a] = std::remainder(rate[a], 2 * kPi);
    rate /= 2 * h;
    ASSERT_LE(((ja * qd).tail<3>() - rate).norm(), 1e-6 * (1 + rate.norm())) << "state " << k;
    ++checked;
  }
  EXPECT_GT(checked, kStates / 2);
}

TEST_P(ModelProperties, MassMatrixIsSymmetricPositiveDefinite) {
  for (int k = 0; k < kStates; ++k) {
    const JointMatrix m = mass_at(test::random_joint_vector(rng_, n(), kPi));
    ASSERT_LE((m - m.transpose()).norm(), 1e-14 * m.norm());
    const Eigen::SelfAdjointEigenSolver<JointMatrix> eig(m);
    ASSERT_GT(eig.eigenvalues().minCoeff(), 0.0);
    ASSERT_EQ(data_->mass_llt.info(), Eigen::Success);
  }
}

TEST_P(ModelProperties, MassMatrixDerivativeMinusTwoCoriolisIsSkew) {
  const double h = 1e-6;
  for (int k = 0; k < kStates; ++k) {
    const JointVector q = test::random_joint_vector(rng_, n(), kPi);
    const JointVector qd = test::random_joint_vector(rng_, n(), 2.0);
    const JointMatrix m_dot = (mass_at(q + h * qd) - mass_at(q - h * qd)) / (2 * h);
    model::forward_velocity(*robot_, *data_, q, qd);
    JointMatrix c;
    model::coriolis_matrix(*robot_, *data_, c);
    const JointMatrix n_matrix = m_dot - 2 * c;
    ASSERT_LE((n_matrix + n_matrix.transpose()).norm(), 1e-6 * (1 + m_dot.norm())) << "state " << k;
    // The matrix reproduces the Coriolis vector.
    model::coriolis_torques(*robot_, *data_);
    ASSERT_LE((c * qd - data_->coriolis_torque).norm(), 1e-10 * (1 + data_->coriolis_torque.norm()));
  }
}

TEST_P(ModelProperties, ForwardDynamicsInvertsInverseDynamics) {
  for (int k = 0; k < kStates; ++k) {
    const JointVector q = test::random_joint_vector(rng_, n(), kPi);
    const JointVector qd = test::random_joint_vector(rng_, n(), 2.0);
    const JointVector qdd = test::random_joint_vector(rng_, n(), 5.0);
    model::forward_velocity(*robot_, *data_, q, qd);
    JointVector tau(n()), qdd_back(n());
    model::inverse_dynamics(*robot_, *data_, qdd, tau);
    model::forward_dynamics(*robot_, *data_, tau, qdd_back);
    ASSERT_LE((qdd_back - qdd).norm(), 1e-9 * (1 + qdd.norm()));
    // And RNEA equals M qdd + C qd + g.
    model::gravity_torques(*robot_, *data_);
    model::coriolis_torques(*robot_, *data_);
    const JointVector sum = data_->mass_matrix * qdd + data_->coriolis_torque + data_->gravity_torque;
    ASSERT_LE((sum - tau).norm(), 1e-10 * (1 + tau.norm()));
  }
}

// Total energy 1/2 qd^T M qd - m g . c of the free (unactuated) chain, integrated with RK4.
TEST_P(ModelProperties, EnergyIsConservedInFreeMotion) {
  const auto energy = [&](const JointVector& q, const JointVector& qd) {
    const JointMatrix m = mass_at(q);
    model::forward_kinematics(*robot_, *data_, q);
    double first_moment_sum = 0.0;
    Eigen::Vector3d h = Eigen::Vector3d::Zero();
    for (int i = 0; i < n(); ++i) h += data_->inertia[i].first_moment;
    first_moment_sum = -robot_->gravity().dot(h);
    return 0.5 * qd.dot(m * qd) + first_moment_sum;
  };
  const auto accel = [&](const JointVector& q, const JointVector& qd) {
    JointVector qdd(n());
    model::forward_velocity(*robot_, *data_, q, qd);
    model::forward_dynamics(*robot_, *data_, JointVector::Zero(n()), qdd);
    return qdd;
  };
  JointVector q = test::random_joint_vector(rng_, n(), kPi);
  JointVector qd = test::random_joint_vector(rng_, n(), 1.0);
  const double e0 = energy(q, qd);
  const double kinetic0 = 0.5 * qd.dot(mass_at(q) * qd);
  const double dt = 2e-4;
  for (int step = 0; step < 5000; ++step) {  // 1 s
    const JointVector k1v = accel(q, qd), k1q = qd;
    const JointVector k2v = accel(q + 0.5 * dt * k1q, qd + 0.5 * dt * k1v), k2q = qd + 0.5 * dt * k1v;
    const JointVector k3v = accel(q + 0.5 * dt * k2q, qd + 0.5 * dt * k2v), k3q = qd + 0.5 * dt * k2v;
    const JointVector k4v = accel(q + dt * k3q, qd + dt * k3v), k4q = qd + dt * k3v;
    q += dt / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
    qd += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
  const double drift = std::abs(energy(q, qd) - e0);
  EXPECT_LT(drift, 1e-7 * (1 + kinetic0)) << "energy " << e0 << " drifted by " << drift;
  EXPECT_GT(qd.norm(), 0.0);
}

TEST_P(ModelProperties, ReflectedDriveInertiaIsOnTheDiagonal) {
  const JointVector q = test::random_joint_vector(rng_, n(), kPi);
  const JointMatrix with_drives = mass_at(q);
  for (int i = 0; i < n(); ++i) {
    const model::DriveData& d = robot_->body(i).drive;
    ASSERT_TRUE(d.present);
    EXPECT_NEAR(robot_->body(i).reflected_inertia,
                (d.rotor_inertia + d.wave_generator_inertia) * d.gear_ratio * d.gear_ratio, 1e-15);
  }
  // Removing the drives changes the diagonal only, by exactly the reflected inertia.
  std::vector<model::Body> bodies = robot_->bodies();
  for (auto& b : bodies) b.reflected_inertia = 0.0;
  const RobotModel rigid(robot_->name(), "", bodies, robot_->frames(), robot_->gravity());
  ModelData rigid_data(rigid);
  model::forward_kinematics(rigid, rigid_data, q);
  model::joint_space_inertia(rigid, rigid_data);
  const JointMatrix diff = with_drives - rigid_data.mass_matrix;
  EXPECT_LE((diff - JointMatrix(robot_->reflected_inertias().asDiagonal())).norm(), 1e-12);
}

TEST_P(ModelProperties, EveryBodyInertiaIsPhysical) {
  for (const model::Body& b : robot_->bodies()) {
    const Eigen::SelfAdjointEigenSolver<JointMatrix> eig{JointMatrix(b.inertia)};
    const Eigen::Vector3d p = eig.eigenvalues();
    EXPECT_GT(b.mass, 0.0) << b.link_name;
    EXPECT_GT(p.minCoeff(), 0.0) << b.link_name;
    // Triangle inequality of the principal moments.
    EXPECT_GE(p[0] + p[1], p[2] - 1e-12) << b.link_name;
    EXPECT_GE(p[1] + p[2], p[0] - 1e-12) << b.link_name;
    EXPECT_GE(p[0] + p[2], p[1] - 1e-12) << b.link_name;
  }
}

INSTANTIATE_TEST_SUITE_P(Devices, ModelProperties, ::testing::ValuesIn(test::kDeviceModels));

// ---- Structural facts of the ViSHaRD models ----

JointVector gravity_at(const RobotModel& robot, ModelData& data, const JointVector& q) {
  model::forward_kinematics(robot, data, q);
  model::gravity_torques(robot, data);
  return data.gravity_torque;
}

void expect_scara_joints_carry_no_gravity(const char* device, int scara_joints) {
  const RobotModel robot = test::load_device_model(device);
  ModelData data(robot);
  std::mt19937_64 rng(3);
  double largest_other = 0.0;
  for (int k = 0; k < 500; ++k) {
    const JointVector g = gravity_at(robot, data, test::random_joint_vector(rng, robot.dof(), kPi));
    for (int i = 0; i < scara_joints; ++i) ASSERT_LT(std::abs(g[i]), 1e-12) << device << " joint " << i + 1;
    largest_other = std::max(largest_other, g.tail(robot.dof() - scara_joints).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(largest_other, 1.0) << device << ": the other joints do carry gravity";
}

TEST(VishardModels, ScaraJointsCarryNoGravityTorque) {
  expect_scara_joints_carry_no_gravity("vishard3", 2);
  expect_scara_joints_carry_no_gravity("vishard6", 3);
  expect_scara_joints_carry_no_gravity("vishard10", 5);
}

// Closest point to a set of lines (least squares) and the largest distance of the lines from it.
std::pair<Eigen::Vector3d, double> common_point(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& lines) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const auto& [point, dir] : lines) {
    const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - dir * dir.transpose();
    a += p;
    b += p * point;
  }
  const Eigen::Vector3d x = a.ldlt().solve(b);
  double worst = 0.0;
  for (const auto& [point, dir] : lines) {
    worst = std::max(worst, ((Eigen::Matrix3d::Identity() - dir * dir.transpose()) * (x - point)).norm());
  }
  return {x, worst};
}

TEST(VishardModels, Vishard10WristAxesMeetInOnePointWithTheMimicElbow) {
  const RobotModel robot = test::load_device_model("vishard10");
  ModelData data(robot);
  const int sensor = robot.require_frame("sensor");
  std::mt19937_64 rng(5);
  double worst_distance = 0.0;
  for (int k = 0; k < 1000; ++k) {
    JointVector q = test::random_joint_vector(rng, 10, kPi);
    q[5] = std::uniform_real_distribution<double>(-1.2, 1.2)(rng);
    q[6] = -2.0 * q[5];  // joints 6 and 7 as a prismatic joint
    model::forward_kinematics(robot, data, q);
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines;
    for (const int joint : {4, 7, 8, 9}) {  // joints 5, 8, 9, 10
      lines.emplace_back(data.position[joint], data.motion_subspace[joint].angular);
    }
    const auto [point, distance] = common_point(lines);
    worst_distance = std::max(worst_distance, distance);
    // The point lies 5 cm in front of the force/torque sensor.
    const Eigen::Vector3d sensor_position = model::frame_pose(robot, data, sensor).translation();
    ASSERT_NEAR((point - sensor_position).norm(), 0.05, 2e-3) << "state " << k;
  }
  // The links of joints 6 and 7 are 0.2122 and 0.2121 m long in the source: the mimic relation then keeps
  // the wrist point on joint 5's axis within 0.1 mm.
  EXPECT_LT(worst_distance, 1.1e-4);
  RecordProperty("worst_axis_distance_m", std::to_string(worst_distance));
}

TEST(VishardModels, Vishard6HandleOrientationHasRankThree) {
  const RobotModel robot = test::load_device_model("vishard6");
  ModelData data(robot);
  const int handle = robot.require_frame("handle");
  std::mt19937_64 rng(6);
  for (int k = 0; k < 500; ++k) {
    model::forward_kinematics(robot, data, test::random_joint_vector(rng, 6, kPi));
    TaskJacobian j, rotation;
    model::frame_jacobian(robot, data, handle, j);
    model::select_rows(j, model::TaskRows::rotation, rotation);
    // The smallest singular value above 1e-3 is the smallest eigenvalue of R R^T above 1e-6 (one solver type
    // for the whole file: each solver instantiated costs this test's compile seconds, an SVD tens of seconds).
    const JointMatrix gram = rotation * rotation.transpose();
    const Eigen::SelfAdjointEigenSolver<JointMatrix> eig(gram);
    ASSERT_GT(eig.eigenvalues().minCoeff(), 1e-6) << "state " << k;
  }
}

TEST(VishardModels, Vishard3ApparentMassSpansThePublishedRange) {
  // Published: apparent end-effector mass 1.9 .. 18 kg over the workspace. Check the order of magnitude of
  // the translational operational-space inertia's eigenvalues over random configurations.
  const RobotModel robot = test::load_device_model("vishard3");
  ModelData data(robot);
  const int handle = robot.require_frame("handle");
  std::mt19937_64 rng(9);
  double lightest = 1e9, heaviest = 0.0;
  for (int k = 0; k < 500; ++k) {
    JointVector q = test::random_joint_vector(rng, 3, kPi);
    q[1] = std::uniform_real_distribution<double>(0.6, 2.4)(rng) * (k % 2 ? 1 : -1);  // away from stretched
    model::forward_kinematics(robot, data, q);
    model::joint_space_inertia(robot, data);
    TaskJacobian j, t;
    model::frame_jacobian(robot, data, handle, j);
    model::select_rows(j, model::TaskRows::translation, t);
    model::TaskMatrix lambda;
    ASSERT_TRUE(model::operational_space_inertia(data, t, lambda));
    const Eigen::SelfAdjointEigenSolver<JointMatrix> eig{JointMatrix(lambda)};
    lightest = std::min(lightest, eig.eigenvalues().minCoeff());
    heaviest = std::max(heaviest, eig.eigenvalues().maxCoeff());
  }
  RecordProperty("apparent_mass_min_kg", std::to_string(lightest));
  RecordProperty("apparent_mass_max_kg", std::to_string(heaviest));
  EXPECT_GT(lightest, 0.5);
  EXPECT_LT(lightest, 5.0);
  EXPECT_GT(heaviest, 10.0);
}

}  // namespace
}  // namespace hapticd

namespace hapticd {
namespace {

TEST(TaskSpace, MinimumNormSolutionIsExactAndHasNoNullSpacePart) {
  const model::RobotModel robot = test::load_device_model("vishard10");
  model::ModelData data(robot);
  std::mt19937_64 rng(12);
  for (int k = 0; k < 100; ++k) {
    model::forward_kinematics(robot, data, test::random_joint_vector(rng, 10, kPi));
    model::TaskJacobian j;
    model::frame_jacobian(robot, data, robot.require_frame("handle"), j);
    const model::TaskVector v = test::random_joint_vector(rng, 6, 1.0).head(6);
    const JointVector q = model::minimum_norm_solution(j, v, 0.0);
    EXPECT_LE((j * q - v).norm(), 1e-8 * (1 + v.norm()));
    // Minimum norm: q lies in the row space of J (no component in its null space).
    const Eigen::MatrixXd jd = j;
    const Eigen::MatrixXd null_projector =
        Eigen::MatrixXd::Identity(10, 10) - jd.completeOrthogonalDecomposition().pseudoInverse() * jd;
    EXPECT_LE((null_projector * Eigen::VectorXd(q)).norm(), 1e-8 * (1 + q.norm()));
  }
}

TEST(TaskSpace, JacobianTransposeTimesUsesTheGivenRows) {
  const model::RobotModel robot = test::load_device_model("vishard6");
  model::ModelData data(robot);
  std::mt19937_64 rng(13);
  model::forward_kinematics(robot, data, test::random_joint_vector(rng, 6, kPi));
  model::TaskJacobian j;
  model::frame_jacobian(robot, data, robot.require_frame("handle"), j);
  model::Vector6d w;
  w << 1, -2, 3, 0.1, 0.2, -0.3;
  EXPECT_LE((model::jacobian_transpose_times(j, 6, w) - j.transpose() * w).norm(), 1e-12);
  model::Vector6d force_only = w;
  force_only.tail<3>().setZero();
  EXPECT_LE((model::jacobian_transpose_times(j, 3, w) - j.transpose() * force_only).norm(), 1e-12);
}

}  // namespace
}  // namespace hapticd

namespace hapticd {
namespace {

TEST(TaskSpace, TaskRowsFollowTheChoiceAndTheDevice) {
  EXPECT_EQ(model::task_rows("auto", 3), 3);
  EXPECT_EQ(model::task_rows("auto", 6), 6);
  EXPECT_EQ(model::task_rows("translation", 10), 3);
  EXPECT_EQ(model::task_rows("full", 6), 6);
  try {
    (void)model::task_rows("full", 3);
    FAIL() << "a 6-D task on 3 joints was accepted";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.key(), "task");
  }
}

}  // namespace
}  // namespace hapticd
