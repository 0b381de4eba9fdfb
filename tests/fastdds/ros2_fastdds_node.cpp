// ROS 2's other default middleware against the server's ROS 2 topics (docs/ros2.md, "Tested"): a participant of
// eProsima Fast DDS - the DDS under rmw_fastrtps - with the types fastddsgen makes of the same rosidl-generated IDL
// (no hapticd code), on the loopback profile config/dds/fastdds-loopback.xml. It does what a ROS 2 node on Fast DDS
// does on the wire: reads a device's pose and joint states (ROS 2's sensor data QoS), /tf (tf2_ros's listener QoS)
// and the robot description (transient local, arriving late), publishes wrench commands (ROS 2's default QoS)
// stamped with the wall clock, and calls the estop and recover services with rmw_cyclonedds's request header.
// Prints one line per check; tests/e2e/ros2_fastdds_test.sh reads them.
//   ros2_fastdds_node PROFILES DOMAIN DEVICE PUSH_N SECONDS
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <string>
#include <thread>

#include "ros2_msg.h"
#include "ros2_msgPubSubTypes.h"

namespace {

using namespace eprosima::fastdds::dds;
using Clock = std::chrono::steady_clock;

struct Node {
  DomainParticipant* participant = nullptr;
  Subscriber* subscriber = nullptr;
  Publisher* publisher = nullptr;

  DataReader* reader(const std::string& topic, const std::string& type, bool reliable, int depth,
                     bool transient_local = false) {
    Topic* t = participant->create_topic(topic, type, TOPIC_QOS_DEFAULT);
    if (t == nullptr) return nullptr;
    DataReaderQos q = DATAREADER_QOS_DEFAULT;
    q.reliability().kind = reliable ? RELIABLE_RELIABILITY_QOS : BEST_EFFORT_RELIABILITY_QOS;
    q.durability().kind = transient_local ? TRANSIENT_LOCAL_DURABILITY_QOS : VOLATILE_DURABILITY_QOS;
    q.history().kind = KEEP_LAST_HISTORY_QOS;
    q.history().depth = depth;
    return subscriber->create_datareader(t, q);
  }
  DataWriter* writer(const std::string& topic, const std::string& type, int depth) {
    Topic* t = participant->create_topic(topic, type, TOPIC_QOS_DEFAULT);
    if (t == nullptr) return nullptr;
    DataWriterQos q = DATAWRITER_QOS_DEFAULT;
    q.reliability().kind = RELIABLE_RELIABILITY_QOS;
    q.durability().kind = VOLATILE_DURABILITY_QOS;
    q.history().kind = KEEP_LAST_HISTORY_QOS;
    q.history().depth = depth;
    return publisher->create_datawriter(t, q);
  }
};

// Waits (at most `seconds`) for a valid sample of `reader`.
template <class T>
bool take(DataReader* reader, T& sample, double seconds) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  SampleInfo info;
  while (Clock::now() < until) {
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK)
      if (info.valid_data) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

double wall_s() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: ros2_fastdds_node PROFILES DOMAIN DEVICE PUSH_N SECONDS\n");
    return 2;
  }
  const std::string profiles = argv[1], device = argv[3];
  const int domain = std::atoi(argv[2]);
  const double push = std::atof(argv[4]), seconds = std::atof(argv[5]);
  auto* factory = DomainParticipantFactory::get_instance();
  if (factory->load_XML_profiles_file(profiles) != ReturnCode_t::RETCODE_OK) return 2;
  Node n;
  n.participant = factory->create_participant_with_profile(domain, "hapticd_participant");
  if (n.participant == nullptr) return 2;
  for (TypeSupport t : {TypeSupport(new geometry_msgs::msg::dds_::PoseStamped_PubSubType()),
                        TypeSupport(new sensor_msgs::msg::dds_::JointState_PubSubType()),
                        TypeSupport(new geometry_msgs::msg::dds_::TwistStamped_PubSubType()),
                        TypeSupport(new tf2_msgs::msg::dds_::TFMessage_PubSubType()),
                        TypeSupport(new std_msgs::msg::dds_::String_PubSubType()),
                        TypeSupport(new geometry_msgs::msg::dds_::WrenchStamped_PubSubType()),
                        TypeSupport(new std_srvs::srv::dds_::Trigger_Request_PubSubType()),
                        TypeSupport(new std_srvs::srv::dds_::Trigger_Response_PubSubType())})
    t.register_type(n.participant);
  n.subscriber = n.participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  n.publisher = n.participant->create_publisher(PUBLISHER_QOS_DEFAULT);
  const std::string ns = "rt/hapticd/" + device + "/";
  DataReader* pose_reader = n.reader(ns + "pose", "geometry_msgs::msg::dds_::PoseStamped_", false, 5);
  DataReader* joint_reader = n.reader(ns + "joint_states", "sensor_msgs::msg::dds_::JointState_", false, 5);
  DataReader* tf_reader = n.reader("rt/tf", "tf2_msgs::msg::dds_::TFMessage_", true, 100);
  DataReader* twist_reader = n.reader(ns + "twist", "geometry_msgs::msg::dds_::TwistStamped_", false, 5);
  DataReader* operator_reader = n.reader(ns + "wrench", "geometry_msgs::msg::dds_::WrenchStamped_", false, 5);
  DataWriter* wrench = n.writer(ns + "wrench_command", "geometry_msgs::msg::dds_::WrenchStamped_", 10);
  DataWriter* estop = n.writer("rq/hapticd/" + device + "/estopRequest", "std_srvs::srv::dds_::Trigger_Request_", 10);
  DataReader* estop_reply =
      n.reader("rr/hapticd/" + device + "/estopReply", "std_srvs::srv::dds_::Trigger_Response_", true, 10);
  DataWriter* recover =
      n.writer("rq/hapticd/" + device + "/recoverRequest", "std_srvs::srv::dds_::Trigger_Request_", 10);
  DataReader* recover_reply =
      n.reader("rr/hapticd/" + device + "/recoverReply", "std_srvs::srv::dds_::Trigger_Response_", true, 10);
  if (!pose_reader || !joint_reader || !tf_reader || !twist_reader || !operator_reader || !wrench || !estop ||
      !estop_reply || !recover || !recover_reply)
    return 2;

  geometry_msgs::msg::dds_::PoseStamped_ pose;
  if (take(pose_reader, pose, 10.0))
    std::printf("pose: frame %s, stamp %.1f s from the wall clock, quaternion norm %.6f\n",
                pose.header().frame_id().c_str(),
                pose.header().stamp().sec() + 1e-9 * pose.header().stamp().nanosec() - wall_s(),
                std::sqrt(pose.pose().orientation().x() * pose.pose().orientation().x() +
                          pose.pose().orientation().y() * pose.pose().orientation().y() +
                          pose.pose().orientation().z() * pose.pose().orientation().z() +
                          pose.pose().orientation().w() * pose.pose().orientation().w()));
  sensor_msgs::msg::dds_::JointState_ joints;
  if (take(joint_reader, joints, 5.0)) {
    std::string names;
    for (const std::string& s : joints.name()) names += (names.empty() ? "" : ",") + s;
    std::printf("joint_states: frame %s, names [%s], %zu positions\n", joints.header().frame_id().c_str(),
                names.c_str(), joints.position().size());
  }
  tf2_msgs::msg::dds_::TFMessage_ tf;
  if (take(tf_reader, tf, 5.0) && tf.transforms().size() == 2)
    std::printf("tf: %s -> %s -> %s\n", tf.transforms()[0].header().frame_id().c_str(),
                tf.transforms()[0].child_frame_id().c_str(), tf.transforms()[1].child_frame_id().c_str());
  geometry_msgs::msg::dds_::TwistStamped_ twist;
  if (take(twist_reader, twist, 5.0)) std::printf("twist: frame %s\n", twist.header().frame_id().c_str());
  geometry_msgs::msg::dds_::WrenchStamped_ operator_wrench;
  if (take(operator_reader, operator_wrench, 5.0))
    std::printf("wrench: frame %s\n", operator_wrench.header().frame_id().c_str());
  // The description: a reader that comes late (transient local).
  DataReader* description_reader = n.reader(ns + "robot_description", "std_msgs::msg::dds_::String_", true, 1, true);
  std_msgs::msg::dds_::String_ description;
  if (description_reader != nullptr && take(description_reader, description, 5.0))
    std::printf("robot_description: %zu bytes, %s\n", description.data().size(),
                description.data().find("<robot") != std::string::npos ? "a URDF" : "not a URDF");

  // Wrench commands at 200 Hz, stamped with the wall clock, as a ROS 2 publisher with the default QoS.
  int sent = 0;
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < until) {
    geometry_msgs::msg::dds_::WrenchStamped_ w;
    const double now = wall_s();
    w.header().stamp().sec(static_cast<int32_t>(now));
    w.header().stamp().nanosec(static_cast<uint32_t>((now - std::floor(now)) * 1e9));
    w.header().frame_id("world");
    w.wrench().force().x(push);
    sent += wrench->write(&w) ? 1 : 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::printf("wrench_command: %d sent\n", sent);

  // The E-stop service, then the recovery (another client of this participant), with rmw_cyclonedds's request
  // header (the client's id, the sequence number), each once its request writer is matched (a volatile request
  // written before would be lost, as a ROS 2 client waits for its service first).
  const auto call = [](DataWriter* w, DataReader* r, std::uint64_t guid, const char* what) {
    for (int i = 0; i < 500; ++i) {
      PublicationMatchedStatus matched;
      if (w->get_publication_matched_status(matched) == ReturnCode_t::RETCODE_OK && matched.current_count > 0) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std_srvs::srv::dds_::Trigger_Request_ request;
    request.client_guid(guid);
    request.sequence_number(1);
    w->write(&request);
    std_srvs::srv::dds_::Trigger_Response_ reply;
    const auto reply_until = Clock::now() + std::chrono::seconds(5);
    while (Clock::now() < reply_until)
      if (take(r, reply, 0.1) && reply.client_guid() == guid && reply.sequence_number() == 1) {
        std::printf("%s: success %d, '%s'\n", what, reply.success() ? 1 : 0, reply.message().c_str());
        return;
      }
  };
  call(estop, estop_reply, 0xfa57dd5ULL, "estop");
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // the safe mode settles first
  call(recover, recover_reply, 0xfa57dd6ULL, "recover");
  n.participant->delete_contained_entities();
  factory->delete_participant(n.participant);
  return 0;
}
