// Run-time parameter sets obey the plugin's schema as the session file does (type, size, bounds): the attack
// set virtual_model.mass_kg to 1e-9 and the device then faulted on speed.
#include <gtest/gtest.h>

#include <cmath>

#include "config/config_error.hpp"
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
      apply_request(d, {DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", {1e-9, 1e-9, 1e-9}});
  EXPECT_FALSE(tiny.accepted);
  EXPECT_NE(tiny.message.find("mass_kg"), std::string::npos) << tiny.message;
  EXPECT_NE(tiny.message.find("0.1"), std::string::npos) << tiny.message;  // says what would be valid
  EXPECT_FALSE(
      apply_request(d, {DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", {2.0, 2.0}}).accepted);  // size
  EXPECT_FALSE(apply_request(d, {DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", {2.0, NAN, 2.0}})
                   .accepted);  // finite
  EXPECT_FALSE(
      apply_request(d, {DeviceRequest::Kind::set_parameter, "virtual_model.damping_n_s_per_m", {-1.0, 0.0, 0.0}})
          .accepted);
  EXPECT_FALSE(
      apply_request(d, {DeviceRequest::Kind::set_parameter, "virtual_model.coupling_stiffness_n_per_m", {1.0, 2.0}})
          .accepted);
  EXPECT_FALSE(apply_request(d, {DeviceRequest::Kind::set_parameter, "virtual_model.rotation", {0.5}})
                   .accepted);  // a boolean takes 0 or 1
  const RuntimeReply ok =
      apply_request(d, {DeviceRequest::Kind::set_parameter, "virtual_model.mass_kg", {2.0, 2.0, 2.0}});
  EXPECT_TRUE(ok.accepted) << ok.message;
  // Requests that are no parameter of the schema stay the plugin's to answer.
  EXPECT_TRUE(apply_request(d, {DeviceRequest::Kind::drive_operator, "release", {}}).accepted);
}

TEST(RuntimeParameters, TheSessionFileHasTheSameBounds) {
  std::string yaml = session();
  yaml.replace(yaml.find("mass_kg: [3.0, 3.0, 3.0]"), 24, "mass_kg: [1e-9, 3.0, 3.0]");
  EXPECT_THROW(test::build_test_session(yaml), ConfigError);
}

}  // namespace
}  // namespace hapticd::server
