// The simulated device plugin in lockstep: sensing as on the hardware (encoder counts, sensor resolution,
// saturation), the attachments (operator, position source, scripted wrench) and switching between them,
// speed monitoring, determinism, configuration errors, allocation-free read/write.
#include <gtest/gtest.h>

#include <thread>

#include "handle_attachment.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "support/handle_mass_urdf.hpp"
#include "support/sim_device_fixture.hpp"

namespace hapticd {
namespace {

using test::SimRig;

const std::string kVishard3 = "urdf: ../urdf/vishard3.urdf\ninitial_position: [-0.3, 1.6, 0.0]\npassive_gimbal: true\n";

TEST(SimDevice, DescribesTheModelAndItsDrives) {
  SimRig rig(kVishard3);
  const DeviceDescription& d = rig.device.description();
  EXPECT_EQ(d.model, "vishard3");
  ASSERT_EQ(d.dof(), 3);
  EXPECT_DOUBLE_EQ(d.joints[0].torque_peak_nm, 54.0);
  EXPECT_NEAR(d.joints[0].velocity_max, 7.645, 1e-3);
  EXPECT_TRUE(d.reports_wrench);
  EXPECT_FALSE(d.reports_joint_velocity);
}

TEST(SimDevice, PositionsAreWholeEncoderCountsAndVelocitiesAreNotReported) {
  // 10 N: well above the gears' break-away (5 N moved joint 1 only 3 counts in 0.2 s with the drive damping 0.3).
  SimRig rig(kVishard3 + "attachment: wrench\nwrench_force: constant\nwrench_force_n: [10, 6, 0]\n");
  const double quantum = 2 * M_PI / (2000.0 * 100.0);
  int distinct = 0;
  double previous = 0.0;
  for (int k = 0; k < 400; ++k) {
    rig.cycle();
    for (int i = 0; i < 3; ++i) {
      const double counts = rig.state.joints.position[i] / quantum;
      ASSERT_NEAR(counts, std::round(counts), 1e-6) << "joint " << i;
      ASSERT_EQ(rig.state.joints.velocity[i], 0.0);
    }
    if (rig.state.joints.position[0] != previous) ++distinct;
    previous = rig.state.joints.position[0];
    // Ground truth differs from the measurement by less than one count, never more.
    const double truth = rig.device.ground_truth().motor_position[0];
    ASSERT_LT(truth - rig.state.joints.position[0], quantum);
    ASSERT_GE(truth - rig.state.joints.position[0], 0.0);
  }
  EXPECT_GT(distinct, 3) << "the joint should move under the pushing wrench";
}

TEST(SimDevice, SensorReadsTheWrenchInResolutionStepsWithinNoise) {
  // Hold the device with a stiff joint PD on the encoder positions; push the handle with 20 N along x.
  SimRig rig(kVishard3 +
             "attachment: wrench\nwrench_force: step\nwrench_force_n: [20, 0, 0]\n"
             "wrench_force_start_s: 0.1\n");
  const JointVector hold = [&] {
    rig.cycle();
    return rig.state.joints.position;
  }();
  double worst = 0.0;
  for (int k = 0; k < 1000; ++k) {
    rig.command.torque_nm = 2000.0 * (hold - rig.state.joints.position);
    rig.cycle();
    const auto& f = rig.state.sensor_wrench.force;
    for (int a = 0; a < 3; ++a) {
      const double lsb = (a == 2 ? 400.0 : 200.0) / 4000.0;
      ASSERT_NEAR(f[a] / lsb, std::round(f[a] / lsb), 1e-6);
    }
    if (k > 400) {
      const Eigen::Vector3d truth = rig.device.ground_truth().sensor_wrench.head<3>();
      worst = std::max(worst, (f - truth).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_NEAR(rig.device.ground_truth().sensor_wrench.head<3>().norm(), 20.0, 1e-6);
  EXPECT_LT(worst, 0.1 * 3);  // 3 LSB: noise of 0.5 LSB plus the rounding
  EXPECT_GT(worst, 0.0);      // but not ideal: noise and quantisation are there
}

TEST(SimDevice, Vishard3SensorMeasuresAccelerations) {
  SimRig rig(kVishard3 +
             "sensor_accelerations: true\nattachment: wrench\nwrench_force: step\n"
             "wrench_force_n: [0, 30, 0]\nwrench_force_start_s: 0.3\n");
  EXPECT_TRUE(rig.device.description().reports_sensor_acceleration);
  JointVector hold;
  for (int k = 0; k < 700; ++k) {
    if (k == 1) hold = rig.state.joints.position;
    if (k >= 1) rig.command.torque_nm = 2000.0 * (hold - rig.state.joints.position);
    rig.cycle();
    const Eigen::Vector3d a = rig.state.sensor_acceleration.linear;
    for (int i = 0; i < 3; ++i) ASSERT_NEAR(a[i] / 0.0981, std::round(a[i] / 0.0981), 1e-6);
    if (k == 550) {
      // Held at rest: the accelerometer reads gravity's reaction, 9.81 m/s^2 upwards.
      EXPECT_NEAR(a.norm(), 9.81, 0.5) << a.transpose();
      EXPECT_NEAR((a - rig.device.ground_truth().sensor_acceleration.head<3>()).norm(), 0.0, 0.1);
    }
  }
  // Released: the pushed, unheld arm accelerates.
  rig.command.torque_nm.setZero();
  double largest = 0.0;
  for (int k = 0; k < 40; ++k) {
    rig.cycle();
    largest =
        std::max(largest, (rig.state.sensor_acceleration.linear -
                           rig.device.ground_truth().handle_pose.linear().transpose() * Eigen::Vector3d(0, 0, 9.81))
                              .norm());
  }
  EXPECT_GT(largest, 1.0);
}

TEST(SimDevice, SensorReadsTheWeightAndInertialForceOfWhatItCarries) {
  const std::string urdf = test::vishard3_urdf_with_handle_mass(0.5);
  const std::string held = "urdf: " + urdf +
                           "\ninitial_position: [-0.3, 1.6, 0.0]\npassive_gimbal: true\nsensor_accelerations: true\n"
                           "attachment: wrench\nwrench_force: step\nwrench_force_n: [0, 20, 0]\n"
                           "wrench_force_start_s: 0.25\n";
  SimRig rig(held);
  const auto& truth = rig.device.ground_truth();
  JointVector hold;
  for (int k = 0; k < 600; ++k) {
    if (k == 1) hold = rig.state.joints.position;
    if (k >= 1) rig.command.torque_nm = 2000.0 * (hold - rig.state.joints.position);
    rig.cycle();
    if (k == 480) {
      // Held still, no external wrench yet: the sensor carries the handle's weight, 0.5 kg * 9.81 m/s^2 down.
      const Eigen::Matrix3d r = truth.handle_pose.linear();
      // (Within what the stiff joint hold lets the handle shake; exactly m (g - a) as the accelerometer has it.)
      EXPECT_NEAR((r * truth.sensor_wrench.head<3>() - Eigen::Vector3d(0, 0, -0.5 * 9.81)).norm(), 0.0, 0.3);
      EXPECT_NEAR((truth.sensor_wrench.head<3>() + 0.5 * truth.sensor_acceleration.head<3>()).norm(), 0.0, 0.05);
    }
  }
  // Released under a 20 N push: the reading is the push plus the weight minus the handle's inertial force, the
  // accelerometer's specific force f = a - g times the mass.
  rig.command.torque_nm.setZero();
  for (int k = 0; k < 100; ++k) rig.cycle();
  double largest_inertial = 0.0;
  for (int k = 0; k < 20; ++k) {
    rig.cycle();
    const Eigen::Matrix3d rt = truth.handle_pose.linear().transpose();
    const Eigen::Vector3d push = rt * Eigen::Vector3d(0, 20, 0);
    const Eigen::Vector3d inertial = 0.5 * truth.sensor_acceleration.head<3>();
    EXPECT_NEAR((truth.sensor_wrench.head<3>() - (push - inertial)).norm(), 0.0, 0.05) << "cycle " << k;
    largest_inertial = std::max(largest_inertial, (inertial - rt * Eigen::Vector3d(0, 0, 0.5 * 9.81)).norm());
  }
  EXPECT_GT(largest_inertial, 1.0) << "the released arm should accelerate the handle";
  // Switched off: the weight only.
  SimRig ideal(held + "sensor_handle_inertia: false\n");
  ideal.command.torque_nm.setZero();
  for (int k = 0; k < 700; ++k) ideal.cycle();
  const auto& t = ideal.device.ground_truth();
  EXPECT_NEAR((t.handle_pose.linear() * t.sensor_wrench.head<3>() - Eigen::Vector3d(0, 20, -0.5 * 9.81)).norm(), 0.0,
              1e-9);
}

TEST(SimDevice, SensorSaturatesAtItsRange) {
  SimRig rig(kVishard3 +
             "attachment: wrench\nwrench_force: constant\nwrench_force_n: [0, 0, -900]\n"
             "speed_monitor: false\n");
  bool saturated = false;
  for (int k = 0; k < 20; ++k) {
    rig.cycle();
    saturated = saturated || rig.device.ground_truth().sensor_saturated;
    ASSERT_LE(rig.state.sensor_wrench.force.cwiseAbs().maxCoeff(), 400.0);
  }
  EXPECT_TRUE(saturated);
  EXPECT_NEAR(rig.state.sensor_wrench.force.cwiseAbs().maxCoeff(), 400.0, 1e-9);
  EXPECT_GT(rig.device.ground_truth().sensor_wrench.head<3>().cwiseAbs().maxCoeff(), 400.0);
}

TEST(SimDevice, OperatorGraspsWithoutJumpAndPushesTheFreeHandle) {
  SimRig rig(kVishard3 +
             "attachment: operator\nfriction: false\noperator_force: step\n"
             "operator_force_n: [0, 10, 0]\noperator_force_start_s: 0.2\n");
  rig.cycle();
  const Eigen::Vector3d start = rig.device.ground_truth().handle_pose.translation();
  for (int k = 0; k < 399; ++k) {
    rig.cycle();
    // Before the push the operator only holds: the grasp carries no more than the arm's own sag.
    if (k < 20) {
      ASSERT_LT(rig.device.ground_truth().handle_wrench.head<3>().norm(), 25.0);
    }
  }
  for (int k = 0; k < 600; ++k) rig.cycle();
  const Eigen::Vector3d moved = rig.device.ground_truth().handle_pose.translation() - start;
  EXPECT_GT(moved.y(), 0.005) << moved.transpose();
}

// The operator's rotation: the hand's inertia on the grasp's rotational spring-damper, pulled by the arm. With
// the handle held still, a voluntary torque step settles at tau k_g / (k_g + k_arm) on the handle, after a
// ring at the hand's damped frequency; a loose grasp passes less of it.
TEST(SimDevice, OperatorHandTurnsTheHandleThroughItsRotationalGrasp) {
  const auto torque_on_a_held_handle = [](double grasp, std::vector<double>& series) {
    sim::AttachmentSettings s;
    s.kind = sim::AttachmentKind::operator_hand;
    s.grasp = grasp;
    s.torque.kind = Profile::Kind::step;
    s.torque.value = Eigen::Vector3d(0, 0, 0.2);
    s.torque.start_s = 0.0;
    sim::HandleAttachment a;
    a.select(s);
    const double dt = 5e-5;
    for (int k = 0; k < 40000; ++k)
      series.push_back(a.step(k * dt, dt, Eigen::Isometry3d::Identity(), sim::Vector6d::Zero())(5));
    return s;
  };
  std::vector<double> firm, loose;
  const sim::AttachmentSettings s = torque_on_a_held_handle(1.0, firm);
  torque_on_a_held_handle(0.0, loose);
  const double k = s.grasp_rotational_stiffness.firm, b = s.grasp_rotational_damping.firm;
  EXPECT_NEAR(firm.back(), 0.2 * k / (k + s.arm_rotational_stiffness), 1e-4);
  const double kl = s.grasp_rotational_stiffness.loose;
  EXPECT_NEAR(loose.back(), 0.2 * kl / (kl + s.arm_rotational_stiffness), 1e-3);
  // The ring at the hand's damped frequency: the transmitted torque crosses its final value every pi / w_d.
  const double wn = std::sqrt((k + s.arm_rotational_stiffness) / s.hand_inertia_kg_m2);
  const double zeta =
      (b + s.arm_rotational_damping) / (2.0 * std::sqrt((k + s.arm_rotational_stiffness) * s.hand_inertia_kg_m2));
  std::vector<double> crossings;
  for (std::size_t i = 1; i < firm.size() && crossings.size() < 2; ++i)
    if ((firm[i - 1] - firm.back()) * (firm[i] - firm.back()) < 0.0) crossings.push_back(static_cast<double>(i) * 5e-5);
  ASSERT_EQ(crossings.size(), 2U);
  const double half_period = M_PI / (wn * std::sqrt(1.0 - zeta * zeta));
  EXPECT_NEAR(crossings[1] - crossings[0], half_period, 0.03 * half_period);
}

TEST(SimDevice, OperatorTwistsTheFreeHandleOfASixDofDevice) {
  // The same device and start with and without a voluntary torque about z: the difference is the operator's.
  const auto rotation_after_half_a_second = [](const std::string& torque) {
    SimRig rig(
        "urdf: ../urdf/vishard6.urdf\ninitial_position: [-0.5, 1.0, -0.5, 0.5, 1.57, 0.0]\nattachment: operator\n"
        "friction: false\noperator_torque: step\noperator_torque_start_s: 0.1\noperator_torque_nm: " +
        torque + "\n");
    rig.cycle();
    const Eigen::Matrix3d start = rig.device.ground_truth().handle_pose.linear();
    for (int k = 0; k < 1000; ++k) rig.cycle();
    const Eigen::AngleAxisd turned(rig.device.ground_truth().handle_pose.linear() * start.transpose());
    return Eigen::Vector3d(turned.angle() * turned.axis());
  };
  const Eigen::Vector3d twisted =
      rotation_after_half_a_second("[0, 0, 0.5]") - rotation_after_half_a_second("[0, 0, 0]");
  EXPECT_GT(twisted.z(), 0.02) << twisted.transpose();
}

TEST(SimDevice, PositionSourceDragsTheHandleAlongItsPath) {
  SimRig rig(kVishard3 + "attachment: position_source\nsource_path: ramp\nsource_path_m: [0.05, 0, 0]\n");
  rig.cycle();
  const Eigen::Vector3d start = rig.device.ground_truth().handle_pose.translation();
  for (int k = 0; k < 2000; ++k) rig.cycle();  // 1 s: 5 cm
  const Eigen::Vector3d moved = rig.device.ground_truth().handle_pose.translation() - start;
  EXPECT_NEAR(moved.x(), 0.05, 1e-3);
  // Dragging a device with friction takes force: the source pushes along the path.
  EXPECT_GT(rig.device.ground_truth().handle_wrench.x(), 1.0);
}

TEST(SimDevice, ShuttlePathHasConstantAccelerationAndConstantVelocityPhases) {
  // 10 cm out and back at 2 m/s^2 and 0.2 m/s: 0.1 s accelerating (1 cm), 0.4 s cruising, 0.1 s braking.
  SimRig rig(kVishard3 +
             "attachment: position_source\nsource_path: shuttle\nsource_path_m: [0.1, 0, 0]\n"
             "source_path_acceleration: 2.0\nsource_path_speed: 0.2\n");
  rig.cycle();
  const Eigen::Vector3d start = rig.device.ground_truth().handle_pose.translation();
  const auto x_at = [&](double t) {
    while (static_cast<double>(rig.index) * 5e-4 < t) rig.cycle();
    return rig.device.ground_truth().handle_pose.translation().x() - start.x();
  };
  EXPECT_NEAR(x_at(0.1), 0.01, 1e-3);  // end of the constant acceleration: a t^2 / 2
  EXPECT_NEAR(x_at(0.3), 0.05, 1e-3);  // cruising at 0.2 m/s
  EXPECT_NEAR(rig.device.ground_truth().handle_twist.x(), 0.2, 0.01);
  EXPECT_NEAR(x_at(0.6), 0.10, 1e-3);  // the far end
  EXPECT_NEAR(x_at(1.2), 0.0, 1e-3);   // back at the start
}

TEST(SimDevice, CommandDelayHoldsTheTorqueBackByTheDeadTime) {
  // A 1 ms dead time: a torque written at 50 ms reaches the drives at 51 ms (current loop off to see it sharp).
  SimRig rig(kVishard3 + "command_delay_s: 0.001\ncurrent_loop: false\nfriction: false\n");
  for (int k = 0; k < 100; ++k) {
    if (k == 100 - 1) rig.command.torque_nm[0] = 2.0;
    rig.cycle();
  }
  // Written at the read of 49.5 ms (cycle 99); due at 50.5 ms.
  rig.cycle();  // read at 50 ms: not yet
  EXPECT_EQ(rig.device.ground_truth().motor_torque[0], 0.0);
  rig.cycle();  // read at 50.5 ms: the substeps up to 50.5 ms ran with the old torque
  rig.cycle();  // read at 51 ms: applied
  EXPECT_NEAR(rig.device.ground_truth().motor_torque[0], 2.0, 1e-12);
}

TEST(SimDevice, AttachmentSwitchesAtRunTimeWithoutAJump) {
  SimRig rig(kVishard3 + "attachment: operator\noperator_motion: sine\noperator_motion_m: [0.03, 0, 0]\n");
  for (int k = 0; k < 1000; ++k) rig.cycle();
  sim::AttachmentSettings source;
  source.kind = sim::AttachmentKind::position_source;
  std::thread other([&] { rig.device.request_attachment(source); });  // from another thread, as DDS will
  other.join();
  const sim::Vector6d before = rig.device.ground_truth().handle_wrench;
  rig.cycle();
  const sim::Vector6d after = rig.device.ground_truth().handle_wrench;
  // The source anchors where the handle is: only its damping acts on the handle's current velocity.
  const double speed = rig.device.ground_truth().handle_twist.head<3>().norm();
  EXPECT_LT(after.head<3>().norm(), 500.0 * speed + 1.0) << before.transpose() << " -> " << after.transpose();
}

TEST(SimDevice, SpeedMonitorFaultsTheDeviceUntilAFaultResetAtRest) {
  SimRig rig(kVishard3 + "attachment: wrench\nwrench_force: constant\nwrench_force_n: [0, 0, -300]\n");
  Outcome r;
  int cycles = 0;
  for (; cycles < 4000 && r.ok(); ++cycles) r = rig.cycle();
  EXPECT_FALSE(r.ok());
  EXPECT_NE(std::string(r.reason).find("speed monitor"), std::string::npos) << r.reason;
  EXPECT_GE(rig.device.ground_truth().overspeed_joint, 0);
  EXPECT_FALSE(rig.cycle().ok()) << "the fault is latched";
  EXPECT_FALSE(rig.device.reset_fault().ok()) << "still over the limit: the latch stays";
  // The push ends; joint damping slows the arm below its speed limits.
  rig.device.request_attachment(sim::AttachmentSettings{});
  for (int k = 0; k < 2000; ++k) {
    rig.command.torque_nm = -20.0 * rig.device.ground_truth().motor_velocity;
    (void)rig.cycle();
  }
  const Outcome reset = rig.device.reset_fault();
  EXPECT_TRUE(reset.ok()) << reset.reason;
  EXPECT_TRUE(rig.cycle().ok());
}

TEST(SimDevice, LifecycleStepsAnswerWithReasons) {
  SimRig rig(kVishard3 + "homing: true\nbrakes: true\n");
  EXPECT_TRUE(rig.device.description().capabilities.homing);
  EXPECT_TRUE(rig.device.description().capabilities.brakes);
  // Not homed: the positions are relative to where the device was enabled, and read() says so.
  const Outcome before = rig.cycle();
  EXPECT_FALSE(before.ok());
  EXPECT_NE(std::string(before.reason).find("not homed"), std::string::npos) << before.reason;
  EXPECT_NEAR(rig.state.joints.position[1], 0.0, 1e-3);
  ASSERT_TRUE(rig.device.home().ok());
  ASSERT_TRUE(rig.cycle().ok());
  EXPECT_NEAR(rig.state.joints.position[1], 1.6, 1e-3);  // absolute: the initial position
  rig.device.disable();
  const Outcome off = rig.cycle();
  EXPECT_FALSE(off.ok());
  EXPECT_STREQ(off.reason, "drives not enabled");
  EXPECT_FALSE(rig.device.home().ok());
}

TEST(SimDevice, SameSeedSameReadingsOtherSeedOtherReadings) {
  const std::string yaml = kVishard3 + "attachment: operator\noperator_motion: sine\noperator_motion_m: [0.03, 0, 0]\n";
  const auto run = [&](std::uint64_t seed) {
    SimRig rig(yaml, 2000.0, seed);
    std::vector<double> out;
    for (int k = 0; k < 2000; ++k) {
      rig.command.torque_nm = JointVector::Constant(3, 0.5);
      rig.cycle();
      out.push_back(rig.state.joints.position[0]);
      out.push_back(rig.state.sensor_wrench.force.x());
    }
    return out;
  };
  EXPECT_EQ(run(1), run(1));
  EXPECT_NE(run(1), run(2));
}

TEST(SimDevice, ReadAndWriteDoNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting is off under sanitizers";
  SimRig rig(
      "urdf: ../urdf/vishard10.urdf\ninitial_position: [0.3, -0.6, 0.6, -0.6, 0.3, 1.0, -2.0, 1.0, 0.8, 0.0]\n"
      "attachment: operator\noperator_motion: sine\noperator_motion_m: [0.03, 0, 0]\n");
  rig.cycle();
  const std::size_t allocations = testing::count_allocations([&] {
    for (int k = 0; k < 50; ++k) rig.cycle();
  });
  EXPECT_EQ(allocations, 0u);
}

std::string configure_error(const std::string& yaml) {
  try {
    SimRig rig(yaml);
  } catch (const ParameterError& e) {
    return e.key() + ": " + e.what();
  }
  return "";
}

TEST(SimDevice, ConfigurationErrorsNameTheParameter) {
  EXPECT_EQ(configure_error("urdf: ../urdf/nope.urdf\n").rfind("urdf: ", 0), 0u);
  EXPECT_NE(configure_error(kVishard3 + "handle_frame: tip\n").find("handle_frame: "), std::string::npos);
  EXPECT_NE(configure_error("urdf: ../urdf/vishard3.urdf\ninitial_position: [1, 2]\n").find("needs 3 values"),
            std::string::npos);
  // ViSHaRD10's wrist springs need more than 2 kHz of substeps.
  EXPECT_NE(configure_error("urdf: ../urdf/vishard10.urdf\nsubstep_hz: 2000\n").find("substep_hz: "),
            std::string::npos);
  EXPECT_NE(configure_error(kVishard3 + "substep_hz: 30000\n").find("divide the control period"), std::string::npos);
}

}  // namespace
}  // namespace hapticd
