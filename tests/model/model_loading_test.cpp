// Loading URDF models: the shipped ViSHaRD files, the drive extension, and every class of bad model file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hapticd/model/urdf_loader.hpp"
#include "support/device_models.hpp"

namespace hapticd {
namespace {

using model::ModelError;
using model::parse_robot_model;

TEST(ModelLoading, ShippedModelsHaveTheirJointsFramesAndDrives) {
  const struct {
    const char* name;
    int dof;
    double total_mass;
  } expected[] = {{"vishard3", 3, 3.53732 + 1.60926 + 2.02199},
                  {"vishard6", 6, 7.52809 + 7.18310 + 2.24088 + 1.78136 + 1.04128 + 0.78057},
                  {"vishard10", 10, 4.164 + 3.474 + 3.410 + 2.888 + 6.813 + 0.682 + 2.413 + 1.152 + 0.807 + 0.252}};
  for (const auto& e : expected) {
    const model::RobotModel robot = test::load_device_model(e.name);
    EXPECT_EQ(robot.name(), e.name);
    EXPECT_EQ(robot.dof(), e.dof);
    EXPECT_GE(robot.frame_id("handle"), 0) << e.name;
    EXPECT_GE(robot.frame_id("sensor"), 0) << e.name;
    EXPECT_GE(robot.frame_id("base"), 0) << e.name;
    double mass = 0.0;
    for (const auto& b : robot.bodies()) {
      mass += b.mass;
      EXPECT_TRUE(b.drive.present) << e.name << " " << b.joint_name;
    }
    EXPECT_NEAR(mass, e.total_mass, 1e-9) << e.name;
  }
}

TEST(ModelLoading, DriveDataGivesTheDerivedJointLimits) {
  const model::RobotModel v3 = test::load_device_model("vishard3");
  EXPECT_NEAR(v3.body(0).reflected_inertia, (1.34e-5 + 7.9e-6) * 100 * 100, 1e-12);
  EXPECT_DOUBLE_EQ(v3.peak_torques()[0], 54.0);  // min(gear 54, 2.5 * 100)
  EXPECT_NEAR(v3.body(0).drive.continuous_joint_torque(), 20.1, 1e-12);
  EXPECT_NEAR(v3.speed_limits()[0], 7300.0 / 100.0 * 2 * M_PI / 60.0, 1e-12);
  EXPECT_DOUBLE_EQ(v3.body(0).drive.joint_counts_per_rev(), 200000.0);
  const model::RobotModel v10 = test::load_device_model("vishard10");
  EXPECT_NEAR(v10.speed_limits()[0], 3.665, 1e-3);  // 5600 rpm / 160
  EXPECT_DOUBLE_EQ(v10.peak_torques()[9], 4.8);     // gear-limited
  EXPECT_DOUBLE_EQ(v10.peak_torques()[2], 87.0);    // min(87, 1.07 * 120 = 128.4)
  EXPECT_DOUBLE_EQ(v10.peak_torques()[7], 13.0);    // min(13, 0.538 * 100)
}

TEST(ModelLoading, UnknownFrameIsAnErrorListingTheFrames) {
  const model::RobotModel v3 = test::load_device_model("vishard3");
  EXPECT_EQ(v3.frame_id("nope"), -1);
  try {
    (void)v3.require_frame("nope");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("handle"), std::string::npos) << e.what();
  }
}

std::string two_link(const std::string& extra, const std::string& joint2_type = "revolute") {
  return R"(<?xml version="1.0"?>
<robot name="two">
  <link name="base"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j2" type=")" +
         joint2_type + R"("><parent link="l1"/><child link="l2"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
  <link name="l2"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
)" + extra +
         "</robot>\n";
}

std::string error_of(const std::string& text) {
  try {
    (void)parse_robot_model(text, "model.urdf");
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(ModelLoading, PlainUrdfWithoutDrivesLoads) {
  const model::RobotModel m = parse_robot_model(two_link(""), "model.urdf");
  EXPECT_EQ(m.dof(), 2);
  EXPECT_FALSE(m.body(0).drive.present);
  EXPECT_DOUBLE_EQ(m.peak_torques()[1], 10.0);  // from <limit effort>
  EXPECT_DOUBLE_EQ(m.body(0).position_max, 1.0);
}

TEST(ModelLoading, FixedLinksAreMergedAndBecomeFrames) {
  const std::string tool = R"(<joint name="tool_mount" type="fixed"><parent link="l2"/><child link="tool"/>
    <origin xyz="0.2 0 0"/></joint>
  <link name="tool"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
)";
  const model::RobotModel m = parse_robot_model(two_link(tool), "model.urdf");
  EXPECT_EQ(m.dof(), 2);
  EXPECT_DOUBLE_EQ(m.body(1).mass, 2.0);
  EXPECT_NEAR(m.body(1).com.x(), 0.1, 1e-12);
  // Two unit masses 0.2 apart about their common centre: + 2 * 1 * 0.1^2 about y and z.
  EXPECT_NEAR(m.body(1).inertia(1, 1), 0.1 + 0.01 + 0.02, 1e-12);
  const int tool_frame = m.require_frame("tool");
  EXPECT_EQ(m.frame(tool_frame).body, 1);
  EXPECT_NEAR(m.frame(tool_frame).placement.translation().x(), 0.2, 1e-12);
}

TEST(ModelLoading, XmlSyntaxErrorNamesTheLine) {
  const std::string e = error_of("<?xml version=\"1.0\"?>\n<robot name=\"x\">\n  <link name=\"a\">\n</robot>\n");
  EXPECT_NE(e.find("model.urdf:"), std::string::npos) << e;
  EXPECT_NE(e.find("XML error"), std::string::npos) << e;
}

TEST(ModelLoading, EachBadModelGetsItsOwnMessage) {
  const std::string good_drive =
      R"(gear_ratio="100" gear_peak_torque="54" gear_average_torque="39" stiffness_min="1e4" stiffness_max="1.6e4"
      max_input_speed_rpm="7300" wave_generator_inertia="7.9e-6" motor_stall_torque="2.5"
      motor_continuous_torque="0.201" rotor_inertia="1.34e-5" encoder_counts_per_motor_rev="2000")";
  const struct {
    std::string text;
    std::string message;
  } cases[] = {
      {"<robot name=\"x\"><link name=\"a\"/></robot>", "no movable joint"},
      {"<notrobot/>", "root element is not <robot>"},
      {two_link("", "floating"), "type not supported"},
      {two_link(R"(<joint name="j3" type="revolute"><parent link="l1"/><child link="l3"/><axis xyz="1 0 0"/>
         <limit lower="-1" upper="1" effort="1" velocity="1"/></joint><link name="l3"/>)"),
       "the chain branches below link 'l1'"},
      {two_link("<hapticd_drive joint=\"j1\" " + good_drive + " colour=\"red\"/>\n"), "unknown attribute 'colour'"},
      {two_link("<hapticd_drive joint=\"j9\" " + good_drive + "/>\n"), "joint 'j9' is not a movable joint"},
      {two_link("<hapticd_drive joint=\"j1\" gear_ratio=\"100\"/>\n"), "attribute 'gear_peak_torque' missing"},
      {two_link("<hapticd_drive joint=\"j1\" " + good_drive + "/>\n<hapticd_drive joint=\"j1\" " + good_drive + "/>\n"),
       "second drive for joint 'j1'"},
      {two_link("<hapticd_drive " + good_drive + "/>\n"), "attribute 'joint' missing"},
  };
  for (const auto& c : cases) {
    const std::string e = error_of(c.text);
    EXPECT_NE(e.find(c.message), std::string::npos) << "expected '" << c.message << "', got '" << e << "'";
    EXPECT_EQ(e.rfind("model.urdf", 0), 0u) << e;
  }
}

TEST(ModelLoading, DriveErrorsNameTheLine) {
  std::string text = two_link("<hapticd_drive joint=\"j1\" gear_ratio=\"fast\"/>\n");
  const std::string e = error_of(text);
  // The drive element is on the last line but one.
  const long line = std::count(text.begin(), text.end(), '\n') - 1;
  EXPECT_NE(e.find("model.urdf:" + std::to_string(line) + ": hapticd_drive"), std::string::npos) << e;
  EXPECT_NE(e.find("'gear_ratio' = 'fast'"), std::string::npos) << e;
}

TEST(ModelLoading, MissingFileIsNamed) {
  try {
    (void)model::load_robot_model("/nonexistent/robot.urdf");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robot.urdf: cannot open"), std::string::npos);
  }
}

}  // namespace
}  // namespace hapticd
