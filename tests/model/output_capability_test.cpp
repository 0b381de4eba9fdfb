// The output-capability analysis: the closed-form worst direction (inscribed ball of the polytope) against
// a brute-force search over sampled directions, and the grid evaluation of ViSHaRD3 against its published
// figures (peak force 86 N, velocity 1.0 m/s, acceleration 14.7 m/s^2).
#include "hapticd/model/output_capability.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "support/device_models.hpp"

namespace hapticd {
namespace {

// Largest alpha with |b_i + alpha a_i . u| <= l_i for all i, for one direction u.
double along(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::Vector3d& u) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < a.rows(); ++i) {
    const double s = a.row(i).dot(u);
    if (std::abs(s) < 1e-15) continue;
    best = std::min(best, s > 0 ? (l[i] - b[i]) / s : (-l[i] - b[i]) / s);
  }
  return best;
}

struct Case {
  const char* device;
  model::TaskRows task;
  model::CapabilitySubspace subspace;
};

class OutputCapability : public ::testing::TestWithParam<Case> {};

TEST_P(OutputCapability, ClosedFormIsTheMinimumOverDirections) {
  const Case c = GetParam();
  const model::RobotModel robot = test::load_device_model(c.device);
  const int handle = robot.require_frame("handle");
  model::ModelData data(robot);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 20; ++k) {
    const JointVector q = test::random_joint_vector(rng, robot.dof(), std::numbers::pi);
    const model::PoseCapability p = model::output_capability(robot, data, q, handle, {c.task, c.subspace, true});
    if (!std::isfinite(p.task_condition) || p.task_condition > 1e6) continue;
    // The same quantities by brute force: torque map of a unit force, and the pseudoinverse maps.
    model::TaskJacobian full, j;
    model::forward_kinematics(robot, data, q);
    model::frame_jacobian(robot, data, handle, full);
    model::select_rows(full, c.task, j);
    model::joint_space_inertia(robot, data);
    model::gravity_torques(robot, data);
    const int col = (c.task == model::TaskRows::full && c.subspace == model::CapabilitySubspace::rotation) ? 3 : 0;
    const Eigen::MatrixXd jd = j;
    const Eigen::MatrixXd force_map = jd.transpose().middleCols(col, 3);
    const Eigen::MatrixXd pinv = jd.completeOrthogonalDecomposition().pseudoInverse();
    const Eigen::MatrixXd velocity_map = pinv.middleCols(col, 3);
    const Eigen::MatrixXd accel_map = Eigen::MatrixXd(data.mass_matrix) * velocity_map;
    const Eigen::VectorXd g = data.gravity_torque;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(robot.dof());
    const Eigen::VectorXd tau = robot.peak_torques();
    const Eigen::VectorXd speed = robot.speed_limits();
    double min_force = 1e300, min_velocity = 1e300, min_accel = 1e300;
    for (int s = 0; s < 20000; ++s) {
      const Eigen::Vector3d u = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
      min_force = std::min(min_force, along(force_map, g, tau, u));
      min_velocity = std::min(min_velocity, along(velocity_map, zero, speed, u));
      min_accel = std::min(min_accel, along(accel_map, g, tau, u));
    }
    // Sampling never finds less than the exact minimum, and comes within 2 % of it.
    EXPECT_GE(min_force, p.force.value * (1 - 1e-9));
    EXPECT_LE(min_force, p.force.value * 1.02);
    EXPECT_GE(min_velocity, p.velocity.value * (1 - 1e-9));
    EXPECT_LE(min_velocity, p.velocity.value * 1.02);
    EXPECT_GE(min_accel, p.acceleration.value * (1 - 1e-9));
    EXPECT_LE(min_accel, p.acceleration.value * 1.02);
    // The reported direction attains the value.
    EXPECT_NEAR(std::min(along(force_map, g, tau, p.force.direction), along(force_map, g, tau, -p.force.direction)),
                p.force.value, 1e-9 * (1 + p.force.value));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Devices, OutputCapability,
    ::testing::Values(Case{"vishard3", model::TaskRows::translation, model::CapabilitySubspace::translation},
                      Case{"vishard6", model::TaskRows::full, model::CapabilitySubspace::translation},
                      Case{"vishard6", model::TaskRows::full, model::CapabilitySubspace::rotation},
                      Case{"vishard10", model::TaskRows::full, model::CapabilitySubspace::rotation}),
    [](const ::testing::TestParamInfo<Case>& param_info) {
      return std::string(param_info.param.device) +
             (param_info.param.subspace == model::CapabilitySubspace::rotation ? "_rotation" : "_translation");
    });

TEST(OutputCapabilityGrid, Vishard3MeetsItsPublishedFigures) {
  const model::RobotModel robot = test::load_device_model("vishard3");
  model::WorkspaceGrid grid;
  grid.center = {0.0, 0.40, 0.0};
  grid.size = {0.6, 0.25, 0.4};
  grid.points_per_axis = 5;
  JointVector seed(3);
  seed << -0.3, 1.6, 0.0;
  const model::GridCapability r =
      model::grid_output_capability(robot, robot.require_frame("handle"), grid, seed,
                                    {model::TaskRows::translation, model::CapabilitySubspace::translation, true});
  EXPECT_EQ(r.reached, r.poses);
  // Published: 86 N, 1.0 m/s, 14.7 m/s^2. The model's worst case over the box lies within 15 % of each.
  EXPECT_NEAR(r.force.value, 86.0, 0.15 * 86.0);
  EXPECT_NEAR(r.velocity.value, 1.0, 0.15);
  EXPECT_NEAR(r.acceleration.value, 14.7, 0.15 * 14.7);
  RecordProperty("worst_force_N", std::to_string(r.force.value));
  RecordProperty("worst_velocity_mps", std::to_string(r.velocity.value));
  RecordProperty("worst_acceleration_mps2", std::to_string(r.acceleration.value));
}

}  // namespace
}  // namespace hapticd
