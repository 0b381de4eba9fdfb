// The repulsion between a group's arms (group/repulsion): the spring-damper on the clearance, and the handle force
// that carries the nearest point's force to the joints (exact for the translational ViSHaRD3).
#include "group/repulsion.hpp"

#include <gtest/gtest.h>

#include <random>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/model_data.hpp"
#include "support/device_models.hpp"

namespace hapticd::server {
namespace {

TEST(Repulsion, IsASpringDamperOnTheClearanceThatNeverPulls) {
  const RepulsionSettings s{0.1, 1000.0, 20.0, 20.0};
  EXPECT_EQ(repulsion_magnitude(s, 0.1, 0.0), 0.0);
  EXPECT_EQ(repulsion_magnitude(s, 0.2, -1.0), 0.0);  // beyond the distance nothing, however fast they approach
  EXPECT_DOUBLE_EQ(repulsion_magnitude(s, 0.06, 0.0), 40.0);
  EXPECT_DOUBLE_EQ(repulsion_magnitude(s, 0.06, -0.5), 50.0);           // approaching: damped harder
  EXPECT_DOUBLE_EQ(repulsion_magnitude(s, 0.06, 1.0), 20.0);            // parting
  EXPECT_EQ(repulsion_magnitude(s, 0.06, 5.0), 0.0);                    // parting fast: no pull
  EXPECT_EQ(repulsion_magnitude(RepulsionSettings{}, -1.0, 0.0), 0.0);  // off by default
}

TEST(Repulsion, TheHandleForceCarriesThePointForceToTheJoints) {
  // ViSHaRD3: three joints, the handle's linear Jacobian square - J^T F reproduces the torques exactly.
  const model::RobotModel m = test::load_device_model("vishard3");
  model::ModelData data(m);
  std::mt19937_64 rng(4);
  const JointVector q = test::random_joint_vector(rng, m.dof(), 0.5);
  model::compute_cycle_terms(m, data, q, JointVector::Zero(m.dof()), m.require_frame("handle"));
  ChainState chain;
  chain.model = &m;
  chain.data = &data;
  JointVector torque(3);
  torque << 2.0, -1.0, 0.5;
  const Eigen::Vector3d f = equivalent_handle_force(chain, torque, 1e3);
  const JointVector back = data.frame_jacobian.topRows<3>().transpose() * f;
  EXPECT_LT((back - torque).norm(), 1e-6 * torque.norm()) << back.transpose();
  // Capped at max_force_n, direction kept.
  const Eigen::Vector3d capped = equivalent_handle_force(chain, torque, 0.5 * f.norm());
  EXPECT_NEAR(capped.norm(), 0.5 * f.norm(), 1e-12);
  EXPECT_LT((capped.normalized() - f.normalized()).norm(), 1e-12);
  // Without a model, or with torques of another size: nothing.
  EXPECT_TRUE(equivalent_handle_force(ChainState{}, torque, 10.0).isZero());
  EXPECT_TRUE(equivalent_handle_force(chain, JointVector::Ones(5), 10.0).isZero());
}

}  // namespace
}  // namespace hapticd::server
