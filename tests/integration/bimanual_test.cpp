// Bimanual coupling (groups[i].model: shared_object): two ViSHaRD3 facing each other hold one virtual box that
// rests on a table between their handles. Their simulated operators lift it 10 cm and turn it 30 degrees about
// the vertical (`operator.push` to carry their share of its weight and `operator.move` requests, as
// `hapticctl operator DEVICE push|move` sends them); the box
// follows, the table lets go of it, and the internal force the model reports is the coupling's squeeze given by
// the handles' distance. In lockstep.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "assembly/session_impl.hpp"
#include "hapticd/server/session.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kCoupling = 2000.0;  // N/m, each hand's spring to its grasp point

// A ViSHaRD3 with a simulated operator holding its handle, in admittance display.
std::string hand(const std::string& name, const std::string& base) {
  return test::sim_vishard3_held_yaml(name, base) + test::vishard3_admittance_chain_yaml();
}

// The pair of config/sessions/dual-arm/vishard3-pair.yaml holding a 1 kg box (0.32 x 0.15 x 0.1 m) whose
// bottom rests on a table at table_z.
std::string box_session(double table_z) {
  return "server: {clock: lockstep, seed: 3}\ndevices:\n" + hand("left", "{xyz: [0, 0, 0]}") +
         hand("right", "{xyz: [0.45, 0.558, 0], rpy: [0, 0, 3.141592653589793]}") +
         "groups:\n  - name: hands\n    devices: [left, right]\n    model:\n      plugin: shared_object\n"
         "      parameters: {mass_kg: 1.0, size_m: [0.32, 0.15, 0.10], coupling_stiffness_n_per_m: " +
         std::to_string(kCoupling) + ", table_height_m: " + std::to_string(table_z) + "}\n";
}

struct Box {
  Eigen::Vector3d position;
  Eigen::Quaterniond orientation;
  double internal_force_n = 0.0;
  double table_force_n = 0.0;
};

Box box_of(Session& s) {
  const RuntimeReply r = s.impl().stages.at(0)->model()->handle_request("state", {});
  EXPECT_TRUE(r.accepted) << r.message;
  Box b;
  b.position = Eigen::Vector3d(r.values.at(0), r.values.at(1), r.values.at(2));
  b.orientation = Eigen::Quaterniond(r.values.at(3), r.values.at(4), r.values.at(5), r.values.at(6));
  b.internal_force_n = r.values.at(7);
  b.table_force_n = r.values.at(8);
  return b;
}

double yaw_deg(const Eigen::Quaterniond& q) {
  const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x()) * 180.0 / kPi;
}

void move(Session& s, const std::string& device, const Eigen::Vector3d& d, double duration_s) {
  const RuntimeReply r =
      s.request(device, DeviceRequest{DeviceRequest::Kind::drive_operator, "move", {d.x(), d.y(), d.z(), duration_s}});
  ASSERT_TRUE(r.accepted) << r.message;
}

TEST(Bimanual, TwoOperatorsLiftTheSharedBoxTenCentimetresAndTurnItThirtyDegrees) {
  // The handles' height at rest, for the table under the box.
  double handle_z = 0.0;
  {
    Session probe = test::build_test_session(box_session(-10.0));
    probe.step(1);
    handle_z = probe.device("left").handle_pose.position.z();
  }
  Session s = test::build_test_session(box_session(handle_z - 0.05));
  s.step(1000);  // 0.5 s: the box placed between the hands settles on the table
  const Box resting = box_of(s);
  const double start_yaw = yaw_deg(resting.orientation);
  EXPECT_NEAR(resting.table_force_n, 9.81, 1.0);  // the table carries it
  EXPECT_NEAR(resting.position.z(), handle_z, 0.005);
  const Eigen::Vector3d left0 = s.device("left").handle_pose.position;
  const Eigen::Vector3d right0 = s.device("right").handle_pose.position;
  const double grasp_distance = (right0 - left0).norm();

  // Lift: both operators aim 10 cm up over 1 s and, as people do, carry their half of the weight on purpose
  // (their arms alone would sag under it: 4.9 N on a 300 N/m arm is 1.6 cm), then hold.
  for (const char* name : {"left", "right"}) {
    const RuntimeReply r =
        s.request(name, DeviceRequest{DeviceRequest::Kind::drive_operator, "push", {0.0, 0.0, 4.905, 1.0}});
    ASSERT_TRUE(r.accepted) << r.message;
    move(s, name, {0.0, 0.0, 0.10}, 1.0);
  }
  s.step(3000);
  const Box lifted = box_of(s);
  EXPECT_NEAR(lifted.position.z() - resting.position.z(), 0.10, 0.015);
  EXPECT_EQ(lifted.table_force_n, 0.0);  // off the table
  // Turn: each hand along its arc's chord to where a 30 degree turn about the box's vertical axis takes it.
  const Eigen::Vector3d centre = lifted.position;
  const Eigen::AngleAxisd turn(30.0 * kPi / 180.0, Eigen::Vector3d::UnitZ());
  for (const char* name : {"left", "right"}) {
    const Eigen::Vector3d p = s.device(name).handle_pose.position;
    Eigen::Vector3d r = p - centre;
    r.z() = 0.0;
    move(s, name, turn * r - r, 1.0);
  }
  double largest_squeeze = 0.0;
  for (int k = 0; k < 4000; ++k) {
    s.step(1);
    largest_squeeze = std::max(largest_squeeze, std::abs(box_of(s).internal_force_n));
  }
  const Box turned = box_of(s);
  EXPECT_NEAR(yaw_deg(turned.orientation) - start_yaw, 30.0, 3.0);
  EXPECT_NEAR(turned.position.z() - resting.position.z(), 0.10, 0.015);
  // The internal force is the couplings' squeeze: each hand's spring compressed by half the shortfall of the
  // handles' distance from the grasp points' (at rest, the damping idle; the box's weight acts across the line).
  const double distance = (s.device("right").handle_pose.position - s.device("left").handle_pose.position).norm();
  EXPECT_NEAR(turned.internal_force_n, kCoupling * (grasp_distance - distance) / 2.0, 0.3);
  // Moving the hands along the chords squeezed the box on the way (the chord midpoints are closer together).
  EXPECT_GT(largest_squeeze, 1.0);
  EXPECT_EQ(s.device("left").fault, "");
  EXPECT_EQ(s.device("right").fault, "");
}

TEST(Bimanual, TheGroupModelDoesNotAllocateOnTheLoop) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  Session s = test::build_test_session(box_session(-10.0));  // no table within reach: the box hangs from the hands
  s.step(10);
  const double z0 = box_of(s).position.z();
  testing::AllocationGuard guard;
  for (std::uint64_t k = 10; k < 1010; ++k) s.impl().cycle->run_cycle(test::cycle_at(k), 1.0, 0, 0);
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_LT(box_of(s).position.z(), z0 - 0.001);  // it ran: the box sagged in the hands under its weight
}

TEST(Bimanual, AFailingGroupModelStopsItsGroupAndOnlyIt) {
  for (const std::string failure : {"error", "throw", "nan"}) {
    Session s = test::build_test_session(
        "server: {clock: lockstep}\ndevices:\n" + test::mass_spring_device_yaml("a") +
        test::mass_spring_device_yaml("b") + test::mass_spring_device_yaml("c") +
        "groups:\n  - name: pair\n    devices: [a, b]\n    model: {plugin: test_faulty_group_model, parameters: "
        "{fail_at_cycle: 200, failure: " +
        failure + "}}\n");
    s.step(200);  // cycles 0..199: the model runs
    for (const char* d : {"a", "b", "c"}) EXPECT_EQ(s.device(d).fault, "") << failure << " " << d;
    s.step(1);  // cycle 200 fails
    // The fault says why: the model's own reason (Outcome), or what the group stage saw.
    const std::string why = failure == "error"   ? "the test model fails as told"
                            : failure == "throw" ? "the group's model threw"
                                                 : "the group's model answered a non-finite force";
    for (const char* d : {"a", "b"}) {
      EXPECT_NE(s.device(d).fault.find(why), std::string::npos) << failure << " " << d << ": " << s.device(d).fault;
      EXPECT_EQ(s.device(d).faults, 1u) << failure;
    }
    s.step(100);
    EXPECT_EQ(s.device("c").fault, "") << failure;   // outside the group: runs on
    EXPECT_EQ(s.device("a").faults, 1u) << failure;  // the model is not run again while its hands are stopped
  }
}

TEST(Bimanual, TheGroupModelTakesRunTimeRequestsThroughItsDevices) {
  Session s = test::build_test_session(
      "server: {clock: lockstep}\ndevices:\n" + test::mass_spring_device_yaml("a") +
      test::mass_spring_device_yaml("b") + test::mass_spring_device_yaml("c") +
      "groups:\n  - name: pair\n    devices: [a, b]\n    model: {plugin: test_faulty_group_model, parameters: "
      "{fail_at_cycle: 100000, force_n: 1.0}}\n");
  const auto request = [&](const char* device, DeviceRequest::Kind kind, const char* name, std::vector<double> v) {
    return s.request(device, {kind, name, std::move(v)});
  };
  s.step(10);
  // A tunable parameter, set through one device and read through the other: one model.
  const RuntimeReply set = request("a", DeviceRequest::Kind::set_parameter, "group_model.force_n", {2.5});
  ASSERT_TRUE(set.accepted) << set.message;
  const RuntimeReply got = request("b", DeviceRequest::Kind::get_parameter, "group_model.force_n", {});
  ASSERT_TRUE(got.accepted) << got.message;
  EXPECT_EQ(got.values, std::vector<double>{2.5});
  const RuntimeReply fixed = request("a", DeviceRequest::Kind::set_parameter, "group_model.fail_at_cycle", {5});
  EXPECT_FALSE(fixed.accepted);
  EXPECT_NE(fixed.message.find("not tunable"), std::string::npos) << fixed.message;
  // A device outside any group with a model says so.
  const RuntimeReply none = request("c", DeviceRequest::Kind::set_parameter, "group_model.force_n", {1.0});
  EXPECT_FALSE(none.accepted);
  EXPECT_NE(none.message.find("no group with a model"), std::string::npos) << none.message;
  // The model's own command: it fails at the next cycle, and its group stops.
  const RuntimeReply command = request("b", DeviceRequest::Kind::set_parameter, "group_model.fail_now", {});
  ASSERT_TRUE(command.accepted) << command.message;
  s.step(1);
  EXPECT_NE(s.device("a").fault.find("the test model fails as told"), std::string::npos) << s.device("a").fault;
  EXPECT_EQ(s.device("c").fault, "");
}

TEST(Bimanual, AGroupModelIsCheckedInTheSessionFile) {
  const auto error_of = [](const std::string& model) {
    try {
      (void)test::build_test_session("server: {clock: lockstep}\ndevices:\n" + hand("left", "{xyz: [0, 0, 0]}") +
                                     hand("right", "{xyz: [1, 0, 0]}") +
                                     "groups:\n  - name: hands\n    devices: [left, right]\n    model: " + model +
                                     "\n");
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("{plugin: no_such_model}").find("groups[0].model.plugin"), std::string::npos);
  EXPECT_NE(error_of("{plugin: admittance}").find("groups[0].model.plugin"), std::string::npos);  // wrong kind
  EXPECT_NE(error_of("{plugin: shared_object, parameters: {mass_kg: -1}}").find("groups[0].model.parameters.mass_kg"),
            std::string::npos);
  EXPECT_NE(error_of("{plugin: shared_object, parameters: {size_m: [0.3, 0, 0.1]}}").find("size_m"), std::string::npos);
}

}  // namespace
}  // namespace hapticd::server
