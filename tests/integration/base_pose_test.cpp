// A device's base pose (the session file's `base_pose`): the device stands there in the session's world frame.
// The same device and push, once at the origin and once mounted elsewhere with the push turned with it, move
// the same way: the handle's world pose is the base pose times the unmounted one, the joints are the same. This
// holds only if the server's model, the simulated physics, the virtual model and the partitioned inverse
// kinematics all agree on where the device stands.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <string>

#include "hapticd/server/session.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The partitioned inverse functions' own posture for the handle at (0.2, 0.15, 1.45), axis vertical.
constexpr const char* kPartitioned =
    "[1.159279, -2.318559, 3.996179, -2.532207, -0.304693, -1.146954, 2.293908, -2.717751, 1.570796, 0.0]";

// Puts `base_pose` into the entry of device `name`.
std::string mounted(std::string yaml, const std::string& name, const std::string& base_pose) {
  const std::string entry = "  - name: " + name + "\n";
  const auto at = yaml.find(entry);
  EXPECT_NE(at, std::string::npos);
  yaml.insert(at + entry.size(), "    base_pose: " + base_pose + "\n");
  return yaml;
}

// The ViSHaRD10 in admittance display (partitioned inverse kinematics, computed torque), pushed by a force and
// a torque step (world axes).
std::string vishard10_session(const std::string& force, const std::string& torque) {
  return std::string("server: {clock: lockstep, seed: 7}\ndevices:\n") +
         test::sim_wrench_step_device_yaml("v10", "vishard10", kPartitioned, force, torque) + R"(    virtual_model:
      plugin: admittance
      parameters: {mass_kg: [4, 4, 4], damping_n_s_per_m: [20, 20, 20], inertia_kg_m2: [0.1, 0.1, 0.1],
                   rotational_damping_n_m_s: [0.5, 0.5, 0.5]}
    inverse_kinematics: {plugin: vishard10_ik}
    controller: {plugin: computed_torque, parameters: {task: full, bandwidth_rad_s: 30}}
)";
}

TEST(BasePose, AMountedDeviceMovesAsTheSameDeviceAtTheOriginSeenFromItsBase) {
  // Yaw a quarter turn (gravity stays vertical) and shift: the push along world x becomes a push along world y.
  Session origin = test::build_test_session(vishard10_session("[3, 0, 0]", "[0.0, 0.05, 0.0]"));
  Session moved = test::build_test_session(mounted(vishard10_session("[0, 3, 0]", "[-0.05, 0.0, 0.0]"), "v10",
                                                   "{xyz: [0.8, -0.5, 0.1], rpy: [0, 0, 1.5707963267948966]}"));
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  base.translation() = Eigen::Vector3d(0.8, -0.5, 0.1);

  const DeviceDescription description = moved.description("v10");
  EXPECT_LT((to_isometry(description.base_pose).matrix() - base.matrix()).norm(), 1e-12);
  EXPECT_TRUE(to_isometry(origin.description("v10").base_pose).isApprox(Eigen::Isometry3d::Identity()));

  double largest_travel = 0.0;
  for (int step = 0; step < 20; ++step) {  // 1 s, the push from 0.2 s on
    origin.step(100);
    moved.step(100);
    const DeviceView a = origin.device("v10");
    const DeviceView b = moved.device("v10");
    ASSERT_TRUE(a.fault.empty()) << a.fault;
    ASSERT_TRUE(b.fault.empty()) << b.fault;
    const Eigen::Isometry3d expected = base * to_isometry(a.handle_pose);
    EXPECT_LT((b.handle_pose.position - expected.translation()).norm(), 1e-6) << "at " << b.time_s << " s";
    EXPECT_LT(
        Eigen::AngleAxisd(Eigen::Matrix3d(b.handle_pose.orientation.toRotationMatrix() * expected.linear().transpose()))
            .angle(),
        1e-6)
        << "at " << b.time_s << " s";
    EXPECT_LT((b.state.joints.position - a.state.joints.position).cwiseAbs().maxCoeff(), 1e-6);
    // The ground truth of the simulation is in the world frame too.
    ASSERT_TRUE(b.truth.has_value());
    EXPECT_LT((b.truth->handle_pose.position - expected.translation()).norm(), 1e-3);
    largest_travel = std::max(largest_travel, (a.handle_pose.position - Eigen::Vector3d(0.2, 0.15, 1.45)).norm());
  }
  EXPECT_GT(largest_travel, 0.02) << "the push must move the handle for the comparison to mean something";
}

// Upside down, gravity pulls the other way through the device: the gravity compensation of the controller (the
// server's mounted model) must match the physics (the simulation's mounted model) for the handle to stay.
std::string vishard3_session(const std::string& base_pose) {
  const std::string yaml =
      test::sim_vishard3_session_head("v3", 3) + "        attachment: none\n" + test::vishard3_admittance_chain_yaml();
  return base_pose.empty() ? yaml : mounted(yaml, "v3", base_pose);
}

TEST(BasePose, AnUpsideDownDeviceCompensatesGravityReversed) {
  Session upright = test::build_test_session(vishard3_session(""));
  Session hung = test::build_test_session(vishard3_session("{xyz: [0, 0, 2.0], rpy: [3.141592653589793, 0, 0]}"));
  upright.step(1);
  hung.step(1);
  const Pose upright_start = upright.device("v3").handle_pose;
  const Pose hung_start = hung.device("v3").handle_pose;
  upright.step(2000);
  hung.step(2000);
  const DeviceView a = upright.device("v3");
  const DeviceView b = hung.device("v3");
  ASSERT_TRUE(a.fault.empty()) << a.fault;
  ASSERT_TRUE(b.fault.empty()) << b.fault;
  EXPECT_LT((a.handle_pose.position - upright_start.position).norm(), 2e-3);
  EXPECT_LT((b.handle_pose.position - hung_start.position).norm(), 2e-3);
  // Hung at z = 2 m turned about x, the handle's world z is 2 m minus its upright height.
  EXPECT_NEAR(b.handle_pose.position.z(), 2.0 - a.handle_pose.position.z(), 2e-3);
  // The joints carry the gravity load reversed (within 15 %: the joints' friction holds a part of it, on the side
  // each device came to rest from).
  const JointVector& up = a.command.torque_nm;
  const JointVector& down = b.command.torque_nm;
  const Eigen::Index loaded = [&] {
    Eigen::Index i = 0;
    up.cwiseAbs().maxCoeff(&i);
    return i;
  }();
  EXPECT_GT(std::abs(up[loaded]), 0.5) << "the upright device must carry a gravity load for the test to mean something";
  EXPECT_NEAR(down[loaded], -up[loaded], 0.15 * std::abs(up[loaded]));
}

TEST(BasePose, IsReadFromTheSessionFileWithItsKeyAndLineOnAnError) {
  try {
    (void)test::build_test_session(mounted(vishard3_session(""), "v3", "{xyz: [0, 0], rpy: [0, 0, 0]}"));
    FAIL() << "a base position of two numbers must be refused";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("session.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("devices[0].base_pose.xyz"), std::string::npos) << what;
    EXPECT_NE(what.find(":4"), std::string::npos) << what;  // the line of base_pose
  }
  try {
    (void)test::build_test_session(mounted(vishard3_session(""), "v3", "[1, 2, 3]"));
    FAIL() << "a base pose that is not a mapping must be refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("devices[0].base_pose"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hapticd::server
