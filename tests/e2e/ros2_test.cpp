// ROS 2 sees the devices (docs/ros2.md): a server with a `ros2` section, served as `hapticd` serves it, read by
// readers built from the same rosidl-generated types a ROS 2 node's middleware registers - on ROS domain 166 with the
// loopback-only configuration. Checked against ROS 2's conventions: the DDS topic names ("rt/" + the ROS name;
// ROS 2 design, "Topic and Service name mapping to DDS"), the type names (pkg::msg::dds_::Type_, as rmw_cyclonedds
// and rmw_fastrtps register them), the QoS profiles (rmw's sensor data and default, tf2_ros's broadcaster,
// robot_state_publisher's transient local description), XCDR1 samples (the encapsulation rmw_cyclonedds writes),
// stamps of the wall clock, frames and units (REP 103).
#include <dds/dds.h>
#include <dds/ddsi/ddsi_serdata.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>

#include "e2e/dds_server_rig.hpp"
#include "hapticd/dds/participant.hpp"
#include "ros2_msg.h"
#include "support/test_paths.hpp"

namespace hapticd::server {
namespace {

using e2e::Server;
using namespace std::chrono_literals;

constexpr int kRosDomain = 166;

std::string urdf_path() { return test::source_dir() + "/config/urdf/vishard3.urdf"; }

std::string ros2_session(double rate_hz) {
  return "server: {clock: realtime, seed: 5, realtime_priority: 0, lock_memory: false, duration_s: 60}\n"
         "ros2: {domain_id: " +
         std::to_string(kRosDomain) + ", rate_hz: " + std::to_string(rate_hz) +
         "}\ndevices:\n  - name: v3\n    base_pose: {xyz: [0.1, 0.0, 0.2], rpy: [0, 0, 0.5]}\n" +
         R"(    device:
      plugin: sim
      parameters:
        urdf: )" +
         urdf_path() + R"(
        initial_position: [-0.3, 1.6, 0.0]
        passive_gimbal: true
        attachment: operator
        operator_grasp: 0.7
    controller:
      plugin: impedance
      parameters: {task: translation, force_gain: 0.0}
    safety: {)" +
         e2e::kRealtimeWatchdogs + "}\n";
}

// A reader of one ROS 2 topic with the QoS a ROS 2 subscriber of that profile asks for.
struct TopicReader {
  TopicReader(dds_entity_t participant, const std::string& ros_name, const dds_topic_descriptor_t* type, bool reliable,
              int depth, bool transient_local = false) {
    dds_qos_t* q = dds_create_qos();
    dds_qset_reliability(q, reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT, DDS_MSECS(100));
    dds_qset_history(q, DDS_HISTORY_KEEP_LAST, depth);
    dds_qset_durability(q, transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
    const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
    dds_qset_data_representation(q, 1, &xcdr1);
    topic = dds_create_topic(participant, type, ("rt" + ros_name).c_str(), q, nullptr);
    reader = dds_create_reader(participant, topic, q, nullptr);
    dds_delete_qos(q);
  }
  ~TopicReader() { dds_delete(reader); }
  // Waits (at most `limit`) for a sample and takes the newest into `sample` (the descriptor's C type).
  bool take(void* sample, std::chrono::milliseconds limit = 5000ms) {
    const auto until = std::chrono::steady_clock::now() + limit;
    bool got = false;
    while (!got && std::chrono::steady_clock::now() < until) {
      void* samples[1] = {sample};
      dds_sample_info_t info;
      while (dds_take(reader, samples, &info, 1, 1) > 0) got = got || info.valid_data;
      if (!got) std::this_thread::sleep_for(10ms);
    }
    return got;
  }
  dds_entity_t topic = 0, reader = 0;
};

// What discovery says of the server's ROS 2 writers: type name and QoS by DDS topic name.
struct Publication {
  std::string type;
  dds_reliability_kind_t reliability{};
  dds_durability_kind_t durability{};
  dds_history_kind_t history{};
  int32_t depth = 0;
  std::vector<dds_data_representation_id_t> representations;
};
std::map<std::string, Publication> publications(dds_entity_t participant, std::size_t wanted) {
  std::map<std::string, Publication> found;
  const dds_entity_t reader = dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, nullptr);
  const auto until = std::chrono::steady_clock::now() + 5s;
  while (found.size() < wanted && std::chrono::steady_clock::now() < until) {
    void* samples[16] = {};
    dds_sample_info_t infos[16];
    const int n = dds_take(reader, samples, infos, 16, 16);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto* e = static_cast<const dds_builtintopic_endpoint_t*>(samples[i]);
      if (std::string(e->topic_name).rfind("rt/", 0) != 0) continue;
      Publication p;
      p.type = e->type_name;
      dds_qget_reliability(e->qos, &p.reliability, nullptr);
      dds_qget_durability(e->qos, &p.durability);
      dds_qget_history(e->qos, &p.history, &p.depth);
      uint32_t count = 0;
      dds_data_representation_id_t* ids = nullptr;
      if (dds_qget_data_representation(e->qos, &count, &ids)) {
        p.representations.assign(ids, ids + count);
        dds_free(ids);
      }
      found[e->topic_name] = p;
    }
    if (n > 0) dds_return_loan(reader, samples, n);
    std::this_thread::sleep_for(20ms);
  }
  dds_delete(reader);
  return found;
}

std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Eigen::Vector3d vec(const geometry_msgs_msg_dds__Vector3_& v) { return {v.x, v.y, v.z}; }
Eigen::Quaterniond quat(const geometry_msgs_msg_dds__Quaternion_& q) { return {q.w, q.x, q.y, q.z}; }
double seconds(const builtin_interfaces_msg_dds__Time_& t) { return t.sec + 1e-9 * t.nanosec; }

TEST(Ros2, EveryTopicOnRos2sWireWithItsTypeQosFramesUnitsAndStamps) {
  if (e2e::kSanitized) GTEST_SKIP() << "real-time rates: not under a sanitizer";
  Server server(ros2_session(250.0));
  dds::Participant ros(dds::ParticipantOptions{kRosDomain, {}, {}});
  const dds_entity_t p = ros.get();
  server.start();

  // Discovery: each topic's DDS name, type name and QoS as a ROS 2 node's middleware would make them.
  const std::map<std::string, Publication> pubs = publications(p, 6);
  const struct {
    const char* topic;
    const char* type;
    dds_reliability_kind_t reliability;
    dds_durability_kind_t durability;
    int depth;
  } expected[] = {
      {"rt/hapticd/v3/pose", "geometry_msgs::msg::dds_::PoseStamped_", DDS_RELIABILITY_BEST_EFFORT,
       DDS_DURABILITY_VOLATILE, 5},
      {"rt/hapticd/v3/twist", "geometry_msgs::msg::dds_::TwistStamped_", DDS_RELIABILITY_BEST_EFFORT,
       DDS_DURABILITY_VOLATILE, 5},
      {"rt/hapticd/v3/wrench", "geometry_msgs::msg::dds_::WrenchStamped_", DDS_RELIABILITY_BEST_EFFORT,
       DDS_DURABILITY_VOLATILE, 5},
      {"rt/hapticd/v3/joint_states", "sensor_msgs::msg::dds_::JointState_", DDS_RELIABILITY_BEST_EFFORT,
       DDS_DURABILITY_VOLATILE, 5},
      {"rt/tf", "tf2_msgs::msg::dds_::TFMessage_", DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_VOLATILE, 100},
      {"rt/hapticd/v3/robot_description", "std_msgs::msg::dds_::String_", DDS_RELIABILITY_RELIABLE,
       DDS_DURABILITY_TRANSIENT_LOCAL, 1},
  };
  for (const auto& e : expected) {
    SCOPED_TRACE(e.topic);
    const auto found = pubs.find(e.topic);
    ASSERT_NE(found, pubs.end());
    EXPECT_EQ(found->second.type, e.type);
    EXPECT_EQ(found->second.reliability, e.reliability);
    EXPECT_EQ(found->second.durability, e.durability);
    EXPECT_EQ(found->second.history, DDS_HISTORY_KEEP_LAST);
    EXPECT_EQ(found->second.depth, e.depth);
    EXPECT_EQ(found->second.representations, std::vector<dds_data_representation_id_t>{DDS_DATA_REPRESENTATION_XCDR1});
  }
  EXPECT_EQ(pubs.count("rt/hapticd/v3/buttons"), 0u) << "a joint device has no buttons";

  // The pose: the handle in the world frame, a unit quaternion, stamped with the wall clock.
  TopicReader pose_reader(p, "/hapticd/v3/pose", &geometry_msgs_msg_dds__PoseStamped__desc, false, 5);
  geometry_msgs_msg_dds__PoseStamped_ pose{};
  ASSERT_TRUE(pose_reader.take(&pose));
  EXPECT_STREQ(pose.header.frame_id, "world");
  const double now = 1e-9 * static_cast<double>(dds_time());
  EXPECT_NEAR(seconds(pose.header.stamp), now, 1.0) << "stamps are the wall clock's (seconds since 1970)";
  EXPECT_LT(pose.header.stamp.nanosec, 1'000'000'000u);
  const Eigen::Vector3d handle(pose.pose.position.x, pose.pose.position.y, pose.pose.position.z);
  const Eigen::Vector3d recorded = server.recording().position().back();
  EXPECT_LT((handle - recorded).norm(), 0.002) << "metres, the world frame: the handle as the loop has it";
  EXPECT_NEAR(quat(pose.pose.orientation).norm(), 1.0, 1e-9);
  geometry_msgs_msg_dds__PoseStamped__free(&pose, DDS_FREE_CONTENTS);

  // The joints: the robot model's names, a value each, in the base frame; the twist and wrench in the handle's.
  TopicReader joint_reader(p, "/hapticd/v3/joint_states", &sensor_msgs_msg_dds__JointState__desc, false, 5);
  sensor_msgs_msg_dds__JointState_ joints{};
  ASSERT_TRUE(joint_reader.take(&joints));
  EXPECT_STREQ(joints.header.frame_id, "v3/base");
  ASSERT_EQ(joints.name._length, 3u);
  EXPECT_STREQ(joints.name._buffer[0], "joint1");
  ASSERT_EQ(joints.position._length, 3u);
  EXPECT_EQ(joints.velocity._length, 3u);
  EXPECT_EQ(joints.effort._length, 3u);
  for (std::uint32_t i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(joints.position._buffer[i]));
  sensor_msgs_msg_dds__JointState__free(&joints, DDS_FREE_CONTENTS);
  TopicReader wrench_reader(p, "/hapticd/v3/wrench", &geometry_msgs_msg_dds__WrenchStamped__desc, false, 5);
  geometry_msgs_msg_dds__WrenchStamped_ wrench{};
  ASSERT_TRUE(wrench_reader.take(&wrench));
  EXPECT_STREQ(wrench.header.frame_id, "v3/handle");
  geometry_msgs_msg_dds__WrenchStamped__free(&wrench, DDS_FREE_CONTENTS);

  // TF: world -> v3/base (the URDF's root link, placed by base_pose) -> v3/handle, composing to the pose.
  TopicReader tf_reader(p, "/tf", &tf2_msgs_msg_dds__TFMessage__desc, true, 100);
  tf2_msgs_msg_dds__TFMessage_ tf{};
  ASSERT_TRUE(tf_reader.take(&tf));
  ASSERT_EQ(tf.transforms._length, 2u);
  const auto& a = tf.transforms._buffer[0];
  const auto& b = tf.transforms._buffer[1];
  EXPECT_STREQ(a.header.frame_id, "world");
  EXPECT_STREQ(a.child_frame_id, "v3/base");
  EXPECT_STREQ(b.header.frame_id, "v3/base");
  EXPECT_STREQ(b.child_frame_id, "v3/handle");
  EXPECT_TRUE(vec(a.transform.translation).isApprox(Eigen::Vector3d(0.1, 0.0, 0.2), 1e-12));
  EXPECT_NEAR(Eigen::AngleAxisd(quat(a.transform.rotation)).angle(), 0.5, 1e-12);
  const Eigen::Vector3d tf_handle =
      vec(a.transform.translation) + quat(a.transform.rotation) * vec(b.transform.translation);
  EXPECT_LT((tf_handle - server.recording().position().back()).norm(), 0.002);
  tf2_msgs_msg_dds__TFMessage__free(&tf, DDS_FREE_CONTENTS);

  // The robot description: a reader that comes late still gets the URDF (transient local), as rviz2 does.
  std::this_thread::sleep_for(300ms);
  TopicReader description_reader(p, "/hapticd/v3/robot_description", &std_msgs_msg_dds__String__desc, true, 1, true);
  std_msgs_msg_dds__String_ description{};
  ASSERT_TRUE(description_reader.take(&description));
  EXPECT_EQ(std::string(description.data), file_text(urdf_path()));
  std_msgs_msg_dds__String__free(&description, DDS_FREE_CONTENTS);

  // XCDR1 on the wire: the sample's encapsulation is CDR little-endian (0x00 0x01), as rmw_cyclonedds writes it.
  {
    TopicReader raw(p, "/hapticd/v3/twist", &geometry_msgs_msg_dds__TwistStamped__desc, false, 5);
    ddsi_serdata* data = nullptr;
    dds_sample_info_t info;
    const auto until = std::chrono::steady_clock::now() + 5s;
    int n = 0;
    while ((n = dds_takecdr(raw.reader, &data, 1, &info, DDS_ANY_STATE)) <= 0 &&
           std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(10ms);
    ASSERT_EQ(n, 1);
    unsigned char header[4] = {};
    ddsi_serdata_to_ser(data, 0, sizeof header, header);
    EXPECT_EQ(header[0], 0x00);
    EXPECT_EQ(header[1], 0x01) << "CDR_LE: XCDR1";
    // 4 (encapsulation) + header (stamp 8, frame id "v3/handle": 4 + 10, padded to 8) + 6 doubles.
    EXPECT_EQ(ddsi_serdata_size(data), 4u + 8u + 16u + 48u);
    ddsi_serdata_unref(data);
  }

  // The rate: every 8th of the loop's 2000 states a second (250 Hz).
  const std::uint64_t published = server.bridge().ros2()->published(0);
  const auto cycles = static_cast<double>(server.recording().index().size());
  server.stop();
  server.join();
  EXPECT_NEAR(static_cast<double>(published), cycles / 8.0, cycles / 80.0 + 2.0);
  EXPECT_EQ(server.bridge().ros2()->write_failures(), 0u);
}

}  // namespace
}  // namespace hapticd::server
