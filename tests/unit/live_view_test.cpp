// The live view's pieces without sockets: the Foxglove protocol's messages and the reading of a viewer's
// requests (tests/live_view/ has the end-to-end test with Foxglove's own client), and one device's messages
// (frame transforms, scene, state) for a ViSHaRD3 posture.
#include <gtest/gtest.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <cmath>
#include <limits>
#include <sstream>

#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/urdf_loader.hpp"
#include "live_view/device_view.hpp"
#include "live_view/foxglove_protocol.hpp"
#include "live_view/foxglove_schemas.hpp"
#include "support/test_paths.hpp"

namespace hapticd::server::live_view {
namespace {

using boost::property_tree::ptree;

ptree parse(const std::string& text) {
  std::istringstream in(text);
  ptree tree;
  boost::property_tree::read_json(in, tree);
  return tree;
}

double number(const ptree& t, const std::string& path) { return t.get<double>(path); }

TEST(FoxgloveProtocol, MessageDataIsOpcodeSubscriptionTimeAndPayloadLittleEndian) {
  std::string frame;
  message_data(frame, 0x01020304u, 0x1122334455667788ull, "{}");
  ASSERT_EQ(frame.size(), 1u + 4u + 8u + 2u);
  const std::string expected_header = "\x01\x04\x03\x02\x01\x88\x77\x66\x55\x44\x33\x22\x11";
  EXPECT_EQ(frame.substr(0, 13), expected_header);
  EXPECT_EQ(frame.substr(13), "{}");
}

TEST(FoxgloveProtocol, ServerInfoAndAdvertiseAreTheSpecsJson) {
  const ptree info = parse(server_info_message("hapticd: \"demo\"", "42"));
  EXPECT_EQ(info.get<std::string>("op"), "serverInfo");
  EXPECT_EQ(info.get<std::string>("name"), "hapticd: \"demo\"");  // escaped and read back
  EXPECT_EQ(info.get<std::string>("sessionId"), "42");

  const std::vector<Channel> channels = {{1, "/v3/transforms", kFrameTransformsName, frame_transforms_schema()},
                                         {2, "/v3/state", kDeviceStateName, device_state_schema()}};
  const ptree ad = parse(advertise_message(channels));
  EXPECT_EQ(ad.get<std::string>("op"), "advertise");
  std::vector<std::string> topics;
  for (const auto& [key, c] : ad.get_child("channels")) {
    topics.push_back(c.get<std::string>("topic"));
    EXPECT_EQ(c.get<std::string>("encoding"), "json");
    EXPECT_EQ(c.get<std::string>("schemaEncoding"), "jsonschema");
    // Each schema is JSON itself, an object whose title is the schema's name.
    const ptree schema = parse(c.get<std::string>("schema"));
    EXPECT_EQ(schema.get<std::string>("title"), c.get<std::string>("schemaName"));
    EXPECT_EQ(schema.get<std::string>("type"), "object");
  }
  EXPECT_EQ(topics, (std::vector<std::string>{"/v3/transforms", "/v3/state"}));
  EXPECT_EQ(parse(scene_update_schema()).get<std::string>("title"), kSceneUpdateName);
}

TEST(FoxgloveProtocol, ReadsSubscribeAndUnsubscribe) {
  const ClientRequest sub =
      parse_client_request(R"({"op":"subscribe","subscriptions":[{"id":0,"channelId":3},{"id":7,"channelId":1}]})");
  ASSERT_EQ(sub.kind, ClientRequest::Kind::subscribe) << sub.error;
  ASSERT_EQ(sub.subscriptions.size(), 2u);
  EXPECT_EQ(sub.subscriptions[0].id, 0u);
  EXPECT_EQ(sub.subscriptions[0].channel, 3u);
  EXPECT_EQ(sub.subscriptions[1].id, 7u);
  EXPECT_EQ(sub.subscriptions[1].channel, 1u);

  const ClientRequest unsub = parse_client_request(R"({"op":"unsubscribe","subscriptionIds":[7, 4294967295]})");
  ASSERT_EQ(unsub.kind, ClientRequest::Kind::unsubscribe) << unsub.error;
  EXPECT_EQ(unsub.subscription_ids, (std::vector<std::uint32_t>{7u, 4294967295u}));

  const ClientRequest other = parse_client_request(R"({"op":"getParameters","parameterNames":[]})");
  EXPECT_EQ(other.kind, ClientRequest::Kind::unsupported);
  EXPECT_EQ(other.op, "getParameters");
}

TEST(FoxgloveProtocol, RefusesMalformedRequestsWithAReason) {
  const std::vector<std::string> bad = {
      "",
      "not json",
      "[1, 2]",
      R"({"subscriptions":[]})",
      R"({"op":{"x":1}})",
      R"({"op":"subscribe"})",
      R"({"op":"subscribe","subscriptions":"all"})",
      R"({"op":"subscribe","subscriptions":[{"id":1}]})",
      R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]})",
      R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":1}]})",
      R"({"op":"subscribe","subscriptions":[{"id":1.5,"channelId":1}]})",
      R"({"op":"subscribe","subscriptions":[{"id":"1","channelId":[1]}]})",
      R"({"op":"unsubscribe","subscriptionIds":[{"id":1}]})",
      R"({"op":"unsubscribe","subscriptionIds":["x"]})",
      std::string(20000, '[') + std::string(20000, ']'),  // deep nesting never reaches the parser
      R"({"op":"subscribe","subscriptions":[)" + std::string(kMaxClientMessageBytes, ' ') + "]}",
  };
  for (const std::string& text : bad) {
    const ClientRequest r = parse_client_request(text);
    EXPECT_EQ(r.kind, ClientRequest::Kind::invalid) << text.substr(0, 80);
    EXPECT_FALSE(r.error.empty()) << text.substr(0, 80);
  }
}

class DeviceViewTest : public ::testing::Test {
 protected:
  DeviceViewTest()
      : model_(std::make_shared<const model::RobotModel>(
            model::load_robot_model(hapticd::test::source_dir() + "/config/urdf/vishard3.urdf"))) {
    description_.model = "vishard3";
    for (const auto& b : model_->bodies()) description_.joints.push_back({b.joint_name});
    snapshot_.cycle = 400;
    snapshot_.time_ns = 200'000'000;
    snapshot_.position = JointVector::Zero(3);
    snapshot_.position << 0.3, -0.2, 0.1;
    snapshot_.velocity = JointVector::Zero(3);
    snapshot_.torque = JointVector::Zero(3);
    model::ModelData data(*model_);
    model::forward_kinematics(*model_, data, snapshot_.position);
    const Eigen::Isometry3d handle = model::frame_pose(*model_, data, model_->require_frame("handle"));
    snapshot_.handle_pose.position = handle.translation();
    snapshot_.handle_pose.orientation = Eigen::Quaterniond(handle.rotation());
    snapshot_.target_pose = snapshot_.handle_pose;
  }

  DeviceView view() { return DeviceView("v3", description_, model_, {"impedance", "admittance"}, {0.01}); }

  std::shared_ptr<const model::RobotModel> model_;
  DeviceDescription description_;
  DeviceSnapshot snapshot_;
};

TEST_F(DeviceViewTest, FrameTransformsGiveEveryLinkOfTheModelAtTheSnapshotsPosture) {
  DeviceView v = view();
  std::string out;
  v.frame_transforms(snapshot_, 1'700'000'000'123'456'789ull, out);
  const ptree t = parse(out);
  std::map<std::string, Eigen::Vector3d> frames;
  for (const auto& [key, tf] : t.get_child("transforms")) {
    EXPECT_EQ(tf.get<std::string>("parent_frame_id"), "world");
    EXPECT_EQ(tf.get<std::int64_t>("timestamp.sec"), 1'700'000'000);
    EXPECT_EQ(tf.get<std::int64_t>("timestamp.nsec"), 123'456'789);
    const Eigen::Quaterniond q(number(tf, "rotation.w"), number(tf, "rotation.x"), number(tf, "rotation.y"),
                               number(tf, "rotation.z"));
    EXPECT_NEAR(q.norm(), 1.0, 1e-9);
    frames[tf.get<std::string>("child_frame_id")] =
        Eigen::Vector3d(number(tf, "translation.x"), number(tf, "translation.y"), number(tf, "translation.z"));
  }
  for (const model::Frame& f : model_->frames()) EXPECT_EQ(frames.count("v3/" + f.name), 1u) << f.name;
  EXPECT_EQ(frames.count("v3/proxy"), 0u);  // no engine input
  // The handle link's frame from the joints and the server's handle pose agree.
  ASSERT_EQ(frames.count("v3/handle"), 1u);
  EXPECT_LT((frames["v3/handle"] - snapshot_.handle_pose.position).norm(), 1e-9);
  EXPECT_LT((frames["v3/handle_point"] - snapshot_.handle_pose.position).norm(), 1e-9);
  // Another posture moves the links (nothing is cached across snapshots).
  snapshot_.cycle += 1;
  snapshot_.position[0] += 0.5;
  v.frame_transforms(snapshot_, 0, out);
  bool moved = false;
  const ptree again = parse(out);
  for (const auto& [key, tf] : again.get_child("transforms"))
    if (tf.get<std::string>("child_frame_id") == "v3/handle")
      moved = std::abs(number(tf, "translation.x") - frames["v3/handle"].x()) > 1e-3 ||
              std::abs(number(tf, "translation.y") - frames["v3/handle"].y()) > 1e-3;
  EXPECT_TRUE(moved);
}

TEST_F(DeviceViewTest, SceneDrawsTheLinksMarkersAndForceArrows) {
  snapshot_.operator_wrench.force = Eigen::Vector3d(0.0, 5.0, 0.0);
  snapshot_.environment_wrench.force = Eigen::Vector3d::Zero();
  snapshot_.engine_has_proxy = true;
  snapshot_.engine_proxy_pose.position = snapshot_.handle_pose.position + Eigen::Vector3d(0.01, 0.0, 0.0);
  DeviceView v = view();
  std::string out;
  v.scene_update(snapshot_, 0, out);
  const ptree scene = parse(out);
  std::map<std::string, ptree> entities;
  for (const auto& [key, e] : scene.get_child("entities")) entities[e.get<std::string>("id")] = e;
  ASSERT_EQ(entities.size(), 4u);
  EXPECT_GE(entities["v3/links"].get_child("cylinders").size(), 3u);         // base .. handle
  EXPECT_EQ(entities["v3/links"].get_child("spheres").size(), 5u);           // the frames on moving bodies
  EXPECT_EQ(entities["v3/markers"].get_child("spheres").size(), 3u);         // handle, target, proxy
  EXPECT_EQ(entities["v3/rendered_wrench"].get_child("arrows").size(), 0u);  // no force, no arrow
  const ptree& arrows = entities["v3/operator_wrench"].get_child("arrows");
  ASSERT_EQ(arrows.size(), 1u);
  const ptree& arrow = arrows.front().second;
  // The arrow points along the force (its +x turned onto +y) from the handle, 1 cm per newton.
  const Eigen::Quaterniond q(number(arrow, "pose.orientation.w"), number(arrow, "pose.orientation.x"),
                             number(arrow, "pose.orientation.y"), number(arrow, "pose.orientation.z"));
  EXPECT_LT((q * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-9);
  EXPECT_NEAR(number(arrow, "shaft_length") + number(arrow, "head_length"), 0.05, 1e-12);
  EXPECT_NEAR(number(arrow, "pose.position.x"), snapshot_.handle_pose.position.x(), 1e-12);
}

TEST_F(DeviceViewTest, StateCarriesJointsFlagsSchemeAndWritesNonFiniteAsNull) {
  snapshot_.scheme = 1;
  snapshot_.saturated = true;
  snapshot_.engine_weight = 0.5;
  snapshot_.torque[2] = std::numeric_limits<double>::quiet_NaN();
  DeviceView v = view();
  std::string out;
  v.device_state(snapshot_, 5, out);
  const ptree s = parse(out);  // NaN would not parse
  EXPECT_EQ(s.get<std::string>("device"), "v3");
  EXPECT_EQ(s.get<std::string>("mode"), "running");
  EXPECT_EQ(s.get<std::string>("scheme"), "admittance");
  std::vector<std::string> flags;
  for (const auto& [k, f] : s.get_child("flags")) flags.push_back(f.data());
  EXPECT_EQ(flags, (std::vector<std::string>{"torque_saturated", "engine_active"}));
  std::vector<std::string> names, positions, torques;
  for (const auto& [k, n] : s.get_child("joints.name")) names.push_back(n.data());
  for (const auto& [k, p] : s.get_child("joints.position")) positions.push_back(p.data());
  for (const auto& [k, p] : s.get_child("joints.torque")) torques.push_back(p.data());
  EXPECT_EQ(names, (std::vector<std::string>{"joint1", "joint2", "joint3"}));
  ASSERT_EQ(positions.size(), 3u);
  EXPECT_DOUBLE_EQ(std::stod(positions[1]), -0.2);
  EXPECT_EQ(torques[2], "null");
  EXPECT_EQ(s.get<std::string>("engine.proxy"), "null");
  EXPECT_EQ(s.get<std::string>("safety.fault"), "none");
}

}  // namespace
}  // namespace hapticd::server::live_view
