// ROS 2 sees the devices (docs/ros2.md): a server with a `ros2` section, served as `hapticd` serves it, read by
// readers built from the same rosidl-generated types a ROS 2 node's middleware registers - on ROS domains 166-168 with
// the loopback-only configuration. Checked against ROS 2's conventions: the DDS topic names ("rt/" + the ROS name; ROS
// 2 design, "Topic and Service name mapping to DDS"), the type names (pkg::msg::dds_::Type_, as rmw_cyclonedds and
// rmw_fastrtps register them), the QoS profiles (rmw's sensor data and default, tf2_ros's broadcaster,
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

// ROS 2's QoS of a profile (reliable or best effort, keep last `depth`, volatile or transient local), XCDR1. The
// caller deletes it.
dds_qos_t* ros_qos(bool reliable, int depth, bool transient_local = false) {
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT, DDS_MSECS(100));
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, depth);
  dds_qset_durability(q, transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(q, 1, &xcdr1);
  return q;
}

// A reader of one ROS 2 topic with the QoS a ROS 2 subscriber of that profile asks for.
struct TopicReader {
  TopicReader(dds_entity_t participant, const std::string& ros_name, const dds_topic_descriptor_t* type, bool reliable,
              int depth, bool transient_local = false) {
    dds_qos_t* q = ros_qos(reliable, depth, transient_local);
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

// Two simulated ViSHaRD3s in admittance display (an engine's wrench moves the virtual body): v3 given to ROS, w3 not.
std::string command_session(int ros_domain) {
  return "server: {clock: realtime, seed: 7, realtime_priority: 0, lock_memory: false, duration_s: 60}\n"
         "ros2: {domain_id: " +
         std::to_string(ros_domain) + ", commands: [v3]}\ndevices:\n" +
         test::sim_vishard3_device_yaml("v3", "constant", "[0.0, 0.0, 0.0]") + e2e::coupling_chain_yaml() +
         "    safety: {" + e2e::kRealtimeWatchdogs + "}\n" +
         test::sim_vishard3_device_yaml("w3", "constant", "[0.0, 0.0, 0.0]") + e2e::coupling_chain_yaml() +
         "    safety: {" + e2e::kRealtimeWatchdogs + "}\n";
}

// A ROS 2 node's publisher of wrench commands: the generated type, ROS 2's default QoS (reliable, keep last 10).
struct WrenchPublisher {
  WrenchPublisher(dds_entity_t participant, const std::string& device) {
    dds_qos_t* q = ros_qos(true, 10);
    topic = dds_create_topic(participant, &geometry_msgs_msg_dds__WrenchStamped__desc,
                             ("rt/hapticd/" + device + "/wrench_command").c_str(), q, nullptr);
    writer = dds_create_writer(participant, topic, q, nullptr);
    dds_delete_qos(q);
    for (int i = 0; i < 300; ++i) {  // matched with the server's reader
      dds_publication_matched_status_t m{};
      if (dds_get_publication_matched_status(writer, &m) == DDS_RETCODE_OK && m.current_count > 0) break;
      std::this_thread::sleep_for(10ms);
    }
  }
  ~WrenchPublisher() { dds_delete(writer); }
  // n commands of force (fx, 0, 0) at 200 Hz, stamped now, in `frame`.
  void push(double fx, int n, const char* frame = "world") {
    for (int i = 0; i < n; ++i) {
      geometry_msgs_msg_dds__WrenchStamped_ w{};
      const dds_time_t now = dds_time();
      w.header.stamp.sec = static_cast<std::int32_t>(now / 1'000'000'000);
      w.header.stamp.nanosec = static_cast<std::uint32_t>(now % 1'000'000'000);
      w.header.frame_id = const_cast<char*>(frame);
      w.wrench.force.x = fx;
      (void)dds_write(writer, &w);
      std::this_thread::sleep_for(5ms);
    }
  }
  dds_entity_t topic = 0, writer = 0;
};

TEST(Ros2, AWrenchCommandMovesTheDeviceGivenToRosAndIsRefusedAndCountedForAnyOther) {
  if (e2e::kSanitized) GTEST_SKIP() << "real-time rates: not under a sanitizer";
  Server server(command_session(kRosDomain + 1));
  dds::Participant ros(dds::ParticipantOptions{kRosDomain + 1, {}, {}});
  server.start();
  Doors& doors = server.bridge();
  EXPECT_EQ(doors.owner(0), "ros2") << "a device given to ROS is claimed by ROS for the session";
  EXPECT_EQ(doors.owner(1), "");
  WrenchPublisher v3(ros.get(), "v3"), w3(ros.get(), "w3");
  std::this_thread::sleep_for(300ms);
  const double x0 = server.recording().position().back().x();

  // 8 N along x for 1 s: the admittance's virtual body, and the handle with it, move along +x.
  v3.push(8.0, 200);
  const double moved = server.recording().position().back().x() - x0;
  std::printf("8 N along x from ROS 2 for 1 s: the handle moved %.1f mm, %llu commands accepted\n", 1000 * moved,
              static_cast<unsigned long long>(doors.commands_accepted(0)));
  EXPECT_GT(moved, 0.005) << "the handle moved " << moved << " m";
  EXPECT_GE(doors.commands_accepted(0), 150u);
  EXPECT_EQ(server.device().status().fault(), DeviceFault::none);

  // The same command to the device not given to ROS: refused by the gate, counted, never applied.
  w3.push(8.0, 50);
  EXPECT_EQ(doors.commands_accepted(1), 0u);
  EXPECT_GE(doors.rejected_by_reason(1)[static_cast<std::size_t>(dds::RejectReason::not_owner)], 40u);

  // A NaN wrench, a wrench beyond the gate's bound and a frame the server does not know: refused and counted.
  const std::uint64_t accepted = doors.commands_accepted(0);
  v3.push(std::nan(""), 5);
  v3.push(1e4, 5);
  v3.push(8.0, 5, "elsewhere");
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(doors.commands_accepted(0), accepted);
  EXPECT_GE(doors.rejected_by_reason(0)[static_cast<std::size_t>(dds::RejectReason::non_finite)], 4u);
  EXPECT_GE(doors.rejected_by_reason(0)[static_cast<std::size_t>(dds::RejectReason::out_of_bounds)], 4u);
  EXPECT_GE(doors.ros2()->commands().refused_frames(), 4u);
  // A wrench in the handle's frame is accepted (turned into the world's by the handle's orientation).
  v3.push(2.0, 5, "v3/handle");
  std::this_thread::sleep_for(50ms);
  EXPECT_GE(doors.commands_accepted(0), accepted + 4);
  server.stop();
  server.join();
  EXPECT_EQ(server.device().status().fault(), DeviceFault::none);
}

// A ROS 2 service client as rmw_cyclonedds makes one: a request writer on rq/<name>Request and a reply reader on
// rr/<name>Reply (ROS 2's services default QoS: reliable, volatile, keep last 10), its GUID in every request.
struct TriggerClient {
  TriggerClient(dds_entity_t participant, const std::string& service, std::uint64_t guid_) : guid(guid_) {
    dds_qos_t* q = ros_qos(true, 10);
    request_topic = dds_create_topic(participant, &std_srvs_srv_dds__Trigger_Request__desc,
                                     ("rq" + service + "Request").c_str(), q, nullptr);
    reply_topic = dds_create_topic(participant, &std_srvs_srv_dds__Trigger_Response__desc,
                                   ("rr" + service + "Reply").c_str(), q, nullptr);
    writer = dds_create_writer(participant, request_topic, q, nullptr);
    reader = dds_create_reader(participant, reply_topic, q, nullptr);
    dds_delete_qos(q);
    for (int i = 0; i < 300; ++i) {
      dds_publication_matched_status_t m{};
      dds_subscription_matched_status_t r{};
      if (dds_get_publication_matched_status(writer, &m) == DDS_RETCODE_OK && m.current_count > 0 &&
          dds_get_subscription_matched_status(reader, &r) == DDS_RETCODE_OK && r.current_count > 0)
        break;
      std::this_thread::sleep_for(10ms);
    }
  }
  ~TriggerClient() {
    dds_delete(writer);
    dds_delete(reader);
  }
  // Calls the service; the reply that carries this client's GUID and the request's sequence number.
  std::optional<std::pair<bool, std::string>> call() {
    const std_srvs_srv_dds__Trigger_Request_ request{guid, ++sequence, 0};
    if (dds_write(writer, &request) != DDS_RETCODE_OK) return std::nullopt;
    const auto until = std::chrono::steady_clock::now() + 5s;
    while (std::chrono::steady_clock::now() < until) {
      void* samples[1] = {};
      dds_sample_info_t info;
      while (dds_take(reader, samples, &info, 1, 1) > 0) {
        const auto& r = *static_cast<const std_srvs_srv_dds__Trigger_Response_*>(samples[0]);
        std::optional<std::pair<bool, std::string>> answer;
        if (info.valid_data && r.client_guid == guid && r.sequence_number == sequence)
          answer = std::make_pair(r.success, std::string(r.message));
        dds_return_loan(reader, samples, 1);
        if (answer) return answer;
      }
      std::this_thread::sleep_for(10ms);
    }
    return std::nullopt;
  }
  std::uint64_t guid;
  std::int64_t sequence = 0;
  dds_entity_t request_topic = 0, reply_topic = 0, writer = 0, reader = 0;
};

TEST(Ros2, EstopAndRecoverAsRos2ServicesUnderTheStopLatchRules) {
  if (e2e::kSanitized) GTEST_SKIP() << "real-time rates: not under a sanitizer";
  Server server(command_session(kRosDomain + 2));
  // Two ROS 2 processes (participants) in the session's ROS domain (each test its own: ctest runs them at once); the
  // first stops the device with one service client and recovers it with another (rmw_cyclonedds gives each client a
  // GUID of its own).
  dds::Participant node(dds::ParticipantOptions{kRosDomain + 2, {}, {}});
  dds::Participant other_node(dds::ParticipantOptions{kRosDomain + 2, {}, {}});
  server.start();
  TriggerClient stopper(node.get(), "/hapticd/v3/estop", 0x1234);
  TriggerClient own_recovery(node.get(), "/hapticd/v3/recover", 0x5678);
  TriggerClient other_recovery(other_node.get(), "/hapticd/v3/recover", 0x9999);
  std::this_thread::sleep_for(300ms);

  const auto stopped = stopper.call();
  ASSERT_TRUE(stopped.has_value()) << "no reply to the E-stop";
  EXPECT_TRUE(stopped->first) << stopped->second;
  for (int i = 0; i < 200 && server.device().status().fault() != DeviceFault::emergency_stop; ++i)
    std::this_thread::sleep_for(10ms);
  EXPECT_EQ(server.device().status().fault(), DeviceFault::emergency_stop);

  // Another client may not release the stop; the one that stopped it may.
  const auto refused = other_recovery.call();
  ASSERT_TRUE(refused.has_value());
  EXPECT_FALSE(refused->first);
  EXPECT_NE(refused->second.find("stopped by"), std::string::npos) << refused->second;
  std::this_thread::sleep_for(500ms);  // the safe mode settles before a recovery
  const auto recovered = own_recovery.call();
  ASSERT_TRUE(recovered.has_value());
  EXPECT_TRUE(recovered->first) << recovered->second;
  for (int i = 0; i < 300 && server.device().status().fault() != DeviceFault::none; ++i)
    std::this_thread::sleep_for(10ms);
  EXPECT_EQ(server.device().status().fault(), DeviceFault::none);
  std::printf("ROS 2 services: estop '%s'; another client's recover refused: '%s'; own recover '%s'\n",
              stopped->second.c_str(), refused->second.c_str(), recovered->second.c_str());
  server.stop();
  server.join();
}

}  // namespace
}  // namespace hapticd::server
