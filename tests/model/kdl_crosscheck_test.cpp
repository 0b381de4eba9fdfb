// Randomised cross-check of the model toolbox against Orocos KDL: FK, J, M, C qd and g agree to 1e-9
// relative on thousands of random states per device.
#include <gtest/gtest.h>

#include <numbers>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "kdl_reference.hpp"
#include "support/device_models.hpp"

namespace hapticd {
namespace {

constexpr int kStates = 2000;
constexpr double kRelative = 1e-9;

// |a - b| <= 1e-9 |b| (norms), with an absolute floor for quantities that are exactly zero.
template <typename A, typename B>
::testing::AssertionResult near_relative(const A& a, const B& b, const char* what) {
  const double err = (a - b).norm();
  const double bound = kRelative * b.norm() + 1e-12;
  if (err <= bound) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << what << ": |ours - KDL| = " << err << " > " << bound << "\nours:\n"
                                       << a << "\nKDL:\n"
                                       << b;
}

class KdlCrossCheck : public ::testing::TestWithParam<const char*> {};

TEST_P(KdlCrossCheck, AgreesOnRandomStates) {
  const model::RobotModel robot = test::load_device_model(GetParam());
  const int handle = robot.require_frame("handle");
  model::ModelData data(robot);
  reference::KdlSolvers kdl(robot, handle);
  ASSERT_EQ(static_cast<int>(kdl.chain.getNrOfJoints()), robot.dof());
  const int n = robot.dof();
  const JointVector reflected = robot.reflected_inertias();
  std::mt19937_64 rng(20261122);
  for (int k = 0; k < kStates; ++k) {
    const JointVector q = test::random_joint_vector(rng, n, std::numbers::pi);
    const JointVector qd = test::random_joint_vector(rng, n, 3.0);
    model::compute_cycle_terms(robot, data, q, qd, handle);
    kdl.q.data = q;
    kdl.qd.data = qd;
    kdl.fk.JntToCart(kdl.q, kdl.pose);
    kdl.jacobian.JntToJac(kdl.q, kdl.jac);
    kdl.dynamics.JntToMass(kdl.q, kdl.mass);
    kdl.dynamics.JntToCoriolis(kdl.q, kdl.qd, kdl.coriolis);
    kdl.dynamics.JntToGravity(kdl.q, kdl.gravity);

    const Eigen::Vector3d kdl_position(kdl.pose.p.x(), kdl.pose.p.y(), kdl.pose.p.z());
    Eigen::Matrix3d kdl_rotation;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) kdl_rotation(r, c) = kdl.pose.M(r, c);
    }
    ASSERT_TRUE(near_relative(data.frame_pose.translation(), kdl_position, "handle position")) << "state " << k;
    ASSERT_TRUE(near_relative(data.frame_pose.linear(), kdl_rotation, "handle rotation")) << "state " << k;
    ASSERT_TRUE(near_relative(data.frame_jacobian, kdl.jac.data, "Jacobian")) << "state " << k;
    JointMatrix rigid = data.mass_matrix;
    rigid.diagonal() -= reflected;
    ASSERT_TRUE(near_relative(rigid, kdl.mass.data, "M")) << "state " << k;
    ASSERT_TRUE(near_relative(data.coriolis_torque, kdl.coriolis.data, "C qd")) << "state " << k;
    ASSERT_TRUE(near_relative(data.gravity_torque, kdl.gravity.data, "g")) << "state " << k;
  }
}

TEST_P(KdlCrossCheck, JacobianDotTimesVelocityAgrees) {
  const model::RobotModel robot = test::load_device_model(GetParam());
  const int handle = robot.require_frame("handle");
  model::ModelData data(robot);
  reference::KdlSolvers kdl(robot, handle);
  std::mt19937_64 rng(7);
  for (int k = 0; k < kStates; ++k) {
    const JointVector q = test::random_joint_vector(rng, robot.dof(), std::numbers::pi);
    const JointVector qd = test::random_joint_vector(rng, robot.dof(), 3.0);
    model::forward_velocity(robot, data, q, qd);
    const model::Vector6d ours = model::frame_jacobian_dot_times_qd(robot, data, handle);
    kdl.q_qd.q.data = q;
    kdl.q_qd.qdot.data = qd;
    kdl.jacobian_dot.JntToJacDot(kdl.q_qd, kdl.jac_dot_qd);
    model::Vector6d theirs;
    theirs << kdl.jac_dot_qd.vel.x(), kdl.jac_dot_qd.vel.y(), kdl.jac_dot_qd.vel.z(), kdl.jac_dot_qd.rot.x(),
        kdl.jac_dot_qd.rot.y(), kdl.jac_dot_qd.rot.z();
    // KDL sums the same terms in another order (and through twists): allow 1e-8 relative.
    ASSERT_LE((ours - theirs).norm(), 1e-8 * theirs.norm() + 1e-10) << "state " << k << "\n" << ours << "\n" << theirs;
  }
}

INSTANTIATE_TEST_SUITE_P(Devices, KdlCrossCheck, ::testing::ValuesIn(test::kDeviceModels));

}  // namespace
}  // namespace hapticd
