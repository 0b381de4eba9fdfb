// Run-time parameter sets obey the plugin's schema as the session file does (type, size, bounds): the attack
// set virtual_model.mass_kg to 1e-9 and the device then faulted on speed.
#include <gtest/gtest.h>

#include <cmath>

#include "config/config_error.hpp"
#include "hapticd/server/session.hpp"
#include "session/device_requests.hpp"
#include "session/device_session.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

std::string session() { return test::sim_vishard3_admittance_session("v3", 3); }

TEST(RuntimeParameters, SetsObeyTheSchemaBounds) {
  auto s = test::build_test_session(session());
  DeviceSession& d = *s.impl().devices[0];
  const RuntimeReply tiny =
      d.requests().apply({DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", {1e-9, 1e-9, 1e-9}});
  EXPECT_FALSE(tiny.accepted);
  EXPECT_NE(tiny.message.find("mass_kg"), std::string::npos) << tiny.message;
  EXPECT_NE(tiny.message.find("0.1"), std::string::npos) << tiny.message;  // says what would be valid
  EXPECT_FALSE(
      d.requests().apply({DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", {2.0, 2.0}}).accepted);  // size
  EXPECT_FALSE(d.requests()
                   .apply({DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", {2.0, NAN, 2.0}})
                   .accepted);  // finite
  EXPECT_FALSE(d.requests()
                   .apply({DeviceRequest::Kind::set_parameter, "virtual_model.damping_n_s_per_m", {-1.0, 0.0, 0.0}})
                   .accepted);
  EXPECT_FALSE(d.requests()
                   .apply({DeviceRequest::Kind::set_parameter, "virtual_model.coupling_stiffness_n_per_m", {1.0, 2.0}})
                   .accepted);
  EXPECT_FALSE(d.requests()
                   .apply({DeviceRequest::Kind::set_parameter, "virtual_model.rotation", {0.5}})
                   .accepted);  // a boolean takes 0 or 1
  const RuntimeReply ok =
      d.requests().apply({DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", {2.0, 2.0, 2.0}});
  EXPECT_TRUE(ok.accepted) << ok.message;
  // Requests that are no parameter of the schema stay the plugin's to answer.
  EXPECT_TRUE(d.requests().apply({DeviceRequest::Kind::drive_operator, "release", {}}).accepted);
}

RuntimeReply set(Session& s, const std::string& name, std::vector<double> values) {
  return s.request("v3", {DeviceRequest::Kind::set_parameter, name, std::move(values)});
}
RuntimeReply get(Session& s, const std::string& name) {
  return s.request("v3", {DeviceRequest::Kind::get_parameter, name, {}});
}

TEST(RuntimeParameters, OnlyTunableParametersAreSetAndEveryOneCanBeRead) {
  auto s = test::build_test_session(session());
  const RuntimeReply fixed = set(s, "virtual_model.rotation", {1.0});  // declared, not tunable
  EXPECT_FALSE(fixed.accepted);
  EXPECT_NE(fixed.message.find("not tunable"), std::string::npos) << fixed.message;
  EXPECT_NE(fixed.message.find("mass_kg"), std::string::npos) << fixed.message;  // lists the tunable ones
  const RuntimeReply rotation = get(s, "virtual_model.rotation");                // but readable, as configured
  ASSERT_TRUE(rotation.accepted) << rotation.message;
  EXPECT_EQ(rotation.values, std::vector<double>{0.0});
  EXPECT_EQ(get(s, "virtual_model.mass_kg").values, (std::vector<double>{3.0, 3.0, 3.0}));
  EXPECT_EQ(get(s, "virtual_model.wall_stiffness_n_per_m").values, std::vector<double>{5000.0});  // a default
  ASSERT_TRUE(set(s, "virtual_model.mass_kg", {4.0, 5.0, 6.0}).accepted);
  const RuntimeReply mass = get(s, "virtual_model.mass_kg");
  EXPECT_EQ(mass.values, (std::vector<double>{4.0, 5.0, 6.0}));
  EXPECT_NE(mass.message.find("mass_kg = "), std::string::npos) << mass.message;
  EXPECT_FALSE(set(s, "virtual_model.mass_kg", {0.0, 5.0, 6.0}).accepted);                  // out of bounds
  EXPECT_EQ(get(s, "virtual_model.mass_kg").values, (std::vector<double>{4.0, 5.0, 6.0}));  // unchanged
  const RuntimeReply unknown = get(s, "virtual_model.massa");
  EXPECT_FALSE(unknown.accepted);
  EXPECT_NE(unknown.message.find("mass_kg"), std::string::npos) << unknown.message;   // lists the parameters
  EXPECT_EQ(get(s, "controller.bandwidth_rad_s").values, std::vector<double>{60.0});  // the motion law's default
  ASSERT_TRUE(set(s, "controller.bandwidth_rad_s", {80.0}).accepted);
  EXPECT_EQ(get(s, "controller.bandwidth_rad_s").values, std::vector<double>{80.0});
  EXPECT_FALSE(set(s, "controller.bandwidth_rad_s", {0.0}).accepted);  // > 0
  EXPECT_FALSE(get(s, "planner.x").accepted);
  EXPECT_FALSE(get(s, "mass_kg").accepted);
  EXPECT_EQ(get(s, "safety.passivity_control").values, std::vector<double>{0.0});
  ASSERT_TRUE(set(s, "safety.passivity_control", {1.0}).accepted);
  s.step(1);
  EXPECT_EQ(get(s, "safety.passivity_control").values, std::vector<double>{1.0});
}

// A tuned value reaches the running plugin: a heavier virtual mass moves less under the same push.
TEST(RuntimeParameters, ATunedMassChangesTheRenderedDynamics) {
  const auto travel = [](double mass) {
    auto s = test::build_test_session(session());
    EXPECT_TRUE(set(s, "virtual_model.mass_kg", {mass, mass, mass}).accepted);
    EXPECT_TRUE(set(s, "virtual_model.damping_n_s_per_m", {5.0, 5.0, 5.0}).accepted);
    s.step(20);
    const double x0 = s.device("v3").handle_pose.position.x();
    EXPECT_TRUE(s.request("v3", {DeviceRequest::Kind::drive_operator, "push", {4.0, 0.0, 0.0, 0.0}}).accepted);
    s.step(400);  // 0.2 s
    return s.device("v3").handle_pose.position.x() - x0;
  };
  const double light = travel(3.0);
  const double heavy = travel(9.0);
  EXPECT_GT(light, 0.002);
  EXPECT_LT(heavy, 0.6 * light) << "light " << light << " m, heavy " << heavy << " m";
}

// The plugin's tune() may refuse what the schema allows; the value in effect stays.
TEST(RuntimeParameters, APluginRefusalKeepsTheValueInEffect) {
  std::string yaml = session();
  yaml.replace(yaml.find("plugin: resolved_acceleration"), 29, "plugin: impedance");
  auto s = test::build_test_session(yaml);
  const RuntimeReply kt = set(s, "controller.joint_torque_gain", {2.0});  // the device has no joint torque sensors
  EXPECT_FALSE(kt.accepted);
  EXPECT_NE(kt.message.find("joint torques"), std::string::npos) << kt.message;
  EXPECT_EQ(get(s, "controller.joint_torque_gain").values, std::vector<double>{0.0});
  ASSERT_TRUE(set(s, "controller.force_gain", {1.5}).accepted);
  EXPECT_EQ(get(s, "controller.force_gain").values, std::vector<double>{1.5});
  EXPECT_FALSE(set(s, "controller.gravity_compensation", {0.0}).accepted);  // not tunable
  s.step(10);
  EXPECT_EQ(s.device("v3").fault, "");
}

TEST(RuntimeParameters, TheSessionFileHasTheSameBounds) {
  std::string yaml = session();
  yaml.replace(yaml.find("mass_kg: [3.0, 3.0, 3.0]"), 24, "mass_kg: [1e-9, 3.0, 3.0]");
  EXPECT_THROW(test::build_test_session(yaml), ConfigError);
}

}  // namespace
}  // namespace hapticd::server
