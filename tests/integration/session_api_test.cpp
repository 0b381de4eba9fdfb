// The in-process session API (hapticd/server/session.hpp), as a program outside the server sees it: this test
// links the shared library hapticd::server only, not the server's core. Shipped session files, lockstep, fixed
// seeds.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "hapticd/parameter_info.hpp"
#include "hapticd/server/session.hpp"
#include "support/test_paths.hpp"

namespace hapticd::server {
namespace {

const std::string kSessions = hapticd::test::source_dir() + "/config/sessions/vishard3/";

Session shipped(const std::string& file, std::vector<std::string> overrides = {}) {
  SessionOptions options;
  options.overrides = std::move(overrides);
  return Session::from_file(kSessions + file, options);
}

using Kind = DeviceRequest::Kind;

TEST(SessionApi, StepsAShippedSessionRepeatablyAndReportsEachDevice) {
  Session a = shipped("admittance-resolved-acceleration.yaml", {"server.seed=5"});
  Session b = shipped("admittance-resolved-acceleration.yaml", {"server.seed=5"});
  ASSERT_EQ(a.device_names(), std::vector<std::string>{"vishard3"});
  EXPECT_DOUBLE_EQ(a.period_s(), 0.0005);
  a.step(1000);
  const DeviceView before = a.device("vishard3");
  a.step(200);
  // The simulated operator's sine push from 0.5 s on (its hand a spring-damper on the handle): about 1.4 N at 0.6 s.
  const DeviceView pushed = a.device("vishard3");
  EXPECT_GT(pushed.operator_wrench.force.norm(), 0.5);
  // What the force sensor measured, against what the simulated hand really applied.
  ASSERT_TRUE(pushed.truth.has_value());
  EXPECT_LT((pushed.truth->handle_wrench.force - pushed.operator_wrench.force).norm(), 0.2);
  a.step(800);
  b.step(2000);
  const DeviceView v = a.device("vishard3");
  EXPECT_EQ(v.cycle, 1999u);
  EXPECT_DOUBLE_EQ(v.time_s, 1999 * 0.0005);
  EXPECT_EQ(v.scheme, "default");
  EXPECT_EQ(v.fault, "");
  EXPECT_EQ(v.state.joints.position.size(), 3);
  // The push moved the handle of the admittance display.
  EXPECT_GT((v.handle_pose.position - before.handle_pose.position).norm(), 1e-3);
  EXPECT_GT(v.command.torque_nm.norm(), 0.0);
  // The same seed, the same run, to the bit.
  const DeviceView w = b.device("vishard3");
  EXPECT_EQ(v.state.joints.position, w.state.joints.position);
  EXPECT_EQ(v.command.torque_nm, w.command.torque_nm);
  // The simulation's truth beside the estimate: the encoders' positions within a few resolution steps of the
  // links', the handle the model computes from them within a millimetre of the true one.
  ASSERT_TRUE(v.truth.has_value());
  EXPECT_NEAR(v.truth->time_s, v.time_s, 1e-9);  // the physics advanced to the cycle's time
  EXPECT_LT((v.truth->link_position - v.state.joints.position).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT((v.truth->handle_pose.position - v.handle_pose.position).norm(), 1e-3);
  EXPECT_EQ(a.statistics().cycles, 2000u);
  EXPECT_GT(a.statistics().compute_p50_us, 0.0);
}

TEST(SessionApi, RequestsAsTheDdsInterfaceOffersThem) {
  Session s = shipped("scheme-switching.yaml");
  s.step(400);
  EXPECT_FALSE(s.request("vishard3", {Kind::switch_scheme, "no_such_scheme", {}}).accepted);
  const RuntimeReply bad = s.request("vishard3", {Kind::set_parameter, "virtual_model.mass_kg", {-1.0, 1.0, 1.0}});
  EXPECT_FALSE(bad.accepted);
  EXPECT_NE(bad.message.find("mass_kg"), std::string::npos) << bad.message;
  EXPECT_FALSE(s.request("vishard3", {Kind::set_parameter, "mass_kg", {1.0}}).accepted);  // no stage
  EXPECT_TRUE(s.request("vishard3", {Kind::set_parameter, "virtual_model.mass_kg", {2.0, 2.0, 2.0}}).accepted);
  EXPECT_TRUE(s.request("vishard3", {Kind::switch_scheme, "impedance", {}}).accepted);
  s.step(400);
  DeviceView v = s.device("vishard3");
  EXPECT_EQ(v.scheme, "impedance");
  EXPECT_EQ(v.scheme_switches, 1u);
  EXPECT_EQ(v.fault, "");

  EXPECT_FALSE(s.request("vishard3", {Kind::recover, "", {}}).accepted);  // nothing to recover from
  EXPECT_TRUE(s.request("vishard3", {Kind::emergency_stop, "", {}}).accepted);
  s.step(1);
  v = s.device("vishard3");
  EXPECT_EQ(v.fault, "emergency stop");
  EXPECT_EQ(v.faults, 1u);
  EXPECT_TRUE(s.request("vishard3", {Kind::recover, "", {}}).accepted);
  s.step(2000);  // the safe mode settles, then the chain activates again
  v = s.device("vishard3");
  EXPECT_EQ(v.fault, "");
  EXPECT_EQ(v.recoveries, 1u);
  EXPECT_THROW(s.request("nobody", {Kind::emergency_stop, "", {}}), std::out_of_range);
}

// hapticctl params and get: every parameter of the running scheme's stages and the safety stage's, by index or
// by name, with its declaration and the value in effect (a tuned one after the set).
TEST(SessionApi, DescribesEveryParameterWithItsValueInEffect) {
  Session s = shipped("scheme-switching.yaml");
  s.step(10);
  ASSERT_TRUE(s.request("vishard3", {Kind::set_parameter, "virtual_model.mass_kg", {2.0, 2.5, 3.0}}).accepted);
  std::vector<ParameterInfo> all;
  for (std::size_t k = 0, count = 1; k < count; ++k) {
    const RuntimeReply r = s.request("vishard3", {Kind::describe_parameter, "", {static_cast<double>(k)}});
    ASSERT_TRUE(r.accepted) << r.message;
    const auto d = decode_parameter_info(r.message, r.values);
    ASSERT_TRUE(d.has_value()) << r.message;
    count = d->count;
    all.push_back(d->info);
  }
  ASSERT_GT(all.size(), 20u);
  EXPECT_EQ(all.front().name.rfind("device.", 0), 0u);
  EXPECT_EQ(all.back().name, "safety.passivity_control");
  const auto named = [&](const std::string& name) {
    for (const ParameterInfo& p : all)
      if (p.name == name) return p;
    ADD_FAILURE() << "no " << name;
    return ParameterInfo{};
  };
  const ParameterInfo mass = named("virtual_model.mass_kg");
  EXPECT_EQ(mass.type, ParameterType::real_vector);
  EXPECT_EQ(mass.unit, "kg");
  EXPECT_TRUE(mass.tunable);
  EXPECT_EQ(mass.minimum, 0.1);
  EXPECT_EQ(mass.maximum, 1000.0);
  EXPECT_EQ(mass.value, (std::vector<double>{2.0, 2.5, 3.0}));
  EXPECT_EQ(mass.value_text, "[2, 2.5, 3]");
  const ParameterInfo urdf = named("device.urdf");  // text: the value in the text only, never tunable
  EXPECT_EQ(urdf.type, ParameterType::string);
  EXPECT_FALSE(urdf.tunable);
  EXPECT_TRUE(urdf.value.empty());
  EXPECT_NE(urdf.value_text.find("vishard3.urdf"), std::string::npos);
  const ParameterInfo bandwidth = named("controller.bandwidth_rad_s");
  EXPECT_TRUE(bandwidth.minimum_exclusive);
  EXPECT_EQ(bandwidth.bounds_text(), "> 0, <= 1000");
  // By name, the same; an index past the end, a name the plugin lacks, a stage that does not exist: refused,
  // saying what would be valid.
  const RuntimeReply by_name = s.request("vishard3", {Kind::describe_parameter, "virtual_model.mass_kg", {}});
  ASSERT_TRUE(by_name.accepted);
  EXPECT_EQ(decode_parameter_info(by_name.message, by_name.values)->info.value, mass.value);
  const RuntimeReply past = s.request("vishard3", {Kind::describe_parameter, "", {static_cast<double>(all.size())}});
  EXPECT_FALSE(past.accepted);
  EXPECT_NE(past.message.find("indices 0 to"), std::string::npos) << past.message;
  const RuntimeReply unknown = s.request("vishard3", {Kind::describe_parameter, "controller.no_such", {}});
  EXPECT_FALSE(unknown.accepted);
  EXPECT_NE(unknown.message.find("bandwidth_rad_s"), std::string::npos) << unknown.message;
  EXPECT_FALSE(s.request("vishard3", {Kind::describe_parameter, "gearbox.ratio", {}}).accepted);
  EXPECT_FALSE(decode_parameter_info(unknown.message, unknown.values).has_value());
}

TEST(SessionApi, EngineInputReachesTheVirtualModelWeightedByItsAge) {
  Session s = shipped("admittance-virtual-coupling.yaml");
  s.step(200);
  EXPECT_EQ(s.device("vishard3").engine_weight, 0.0);  // no engine yet
  EngineInput input;
  input.has_wrench = true;
  input.wrench.force = Eigen::Vector3d(0.0, 0.0, 4.0);
  for (int k = 0; k < 400; ++k) {  // a fresh input every cycle, as an engine at the loop's rate sends
    input.sequence = static_cast<std::uint64_t>(k + 1);
    s.set_engine_input("vishard3", input);
    s.step(1);
  }
  const DeviceView v = s.device("vishard3");
  EXPECT_DOUBLE_EQ(v.engine_weight, 1.0);  // ramped in (0.1 s) and fresh
  EXPECT_NEAR(v.task.wrench.force.z(), 4.0, 1e-9);
  s.step(400);  // silent for 0.2 s: past the deadline and the fade
  EXPECT_EQ(s.device("vishard3").engine_weight, 0.0);
}

TEST(SessionApi, StopRampsTheTorqueToZeroAndEndsTheSession) {
  Session s = shipped("admittance-resolved-acceleration.yaml");
  s.step(2000);
  s.stop();
  const DeviceView v = s.device("vishard3");
  EXPECT_EQ(v.command.torque_nm.norm(), 0.0);
  EXPECT_EQ(v.cycle, 2000u + 400u - 1u);  // shutdown_ramp_s 0.2 s
  EXPECT_THROW(s.step(), std::logic_error);
}

TEST(SessionApi, ErrorsNameTheFileLineAndKeyOrTheOverride) {
  try {
    (void)Session::from_yaml("server: {rate_hz: 2000}\ndevices:\n  - name: a\n    devize: {}\n", {}, "mine.yaml");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("mine.yaml:4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("devize"), std::string::npos) << e.what();
  }
  try {
    (void)shipped("admittance-resolved-acceleration.yaml",
                  {"devices.vishard3.virtual_model.parameters.mass_kg=[1, 2]"});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("override 'devices.vishard3.virtual_model.parameters.mass_kg=[1, 2]'"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)shipped("admittance-resolved-acceleration.yaml", {"devices.nobody.controller=1"}),
               std::runtime_error);
  EXPECT_THROW((void)shipped("admittance-resolved-acceleration.yaml", {"no equals sign"}), std::runtime_error);
  Session s = shipped("admittance-resolved-acceleration.yaml");
  EXPECT_THROW((void)s.device("nobody"), std::out_of_range);
}

}  // namespace
}  // namespace hapticd::server
