// A ROS 2 node's subscriptions to one device's topics, on the wire (docs/ros2.md): readers of the rosidl-generated
// types with ROS 2's QoS, on the loopback-only configuration, for SECONDS; prints how many samples each took. The
// reader side of scripts/measure-ros2-cost.sh (the loop's cost of the ROS 2 topics, with someone listening).
//   ros2_subscriber DOMAIN DEVICE SECONDS
//   ros2_subscriber DOMAIN DEVICE SECONDS buttons   a handle device's Joy: the newest buttons and axes, its frame
#include <dds/dds.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "hapticd/dds/participant.hpp"
#include "ros2_msg.h"

int main(int argc, char** argv) {
  if (argc != 4 && !(argc == 5 && std::string(argv[4]) == "buttons")) {
    std::fprintf(stderr, "usage: ros2_subscriber DOMAIN DEVICE SECONDS [buttons]\n");
    return 2;
  }
  const int domain = std::atoi(argv[1]);
  const std::string device = argv[2];
  hapticd::dds::Participant participant(hapticd::dds::ParticipantOptions{domain, {}, {}});
  if (argc == 5) {  // the Joy of a handle device
    dds_qos_t* q = dds_create_qos();
    dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 5);
    const std::string name = "rt/hapticd/" + device + "/buttons";
    const dds_entity_t topic =
        dds_create_topic(participant.get(), &sensor_msgs_msg_dds__Joy__desc, name.c_str(), q, nullptr);
    const dds_entity_t reader = dds_create_reader(participant.get(), topic, q, nullptr);
    dds_delete_qos(q);
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::atof(argv[3]));
    std::string last = "no buttons";
    while (std::chrono::steady_clock::now() < until) {
      void* samples[1] = {};
      dds_sample_info_t info;
      while (dds_take(reader, samples, &info, 1, 1) > 0) {
        const auto& joy = *static_cast<const sensor_msgs_msg_dds__Joy_*>(samples[0]);
        if (info.valid_data) {
          last = "buttons ";
          for (std::uint32_t i = 0; i < joy.buttons._length; ++i)
            last += (i > 0 ? "," : "") + std::to_string(joy.buttons._buffer[i]);
          last += " axes";
          for (std::uint32_t i = 0; i < joy.axes._length; ++i) {
            char v[32];
            std::snprintf(v, sizeof v, " %.3f", joy.axes._buffer[i]);
            last += v;
          }
          last += std::string(" frame ") + joy.header.frame_id;
        }
        dds_return_loan(reader, samples, 1);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    std::printf("%s\n", last.c_str());
    return 0;
  }
  struct Topic {
    const char* name;
    const dds_topic_descriptor_t* type;
    bool reliable;
    int depth;
    dds_entity_t reader = 0;
    long taken = 0;
  } topics[] = {
      {"pose", &geometry_msgs_msg_dds__PoseStamped__desc, false, 5},
      {"twist", &geometry_msgs_msg_dds__TwistStamped__desc, false, 5},
      {"wrench", &geometry_msgs_msg_dds__WrenchStamped__desc, false, 5},
      {"joint_states", &sensor_msgs_msg_dds__JointState__desc, false, 5},
      {"tf", &tf2_msgs_msg_dds__TFMessage__desc, true, 100},
  };
  for (Topic& t : topics) {
    dds_qos_t* q = dds_create_qos();
    dds_qset_reliability(q, t.reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT, DDS_MSECS(100));
    dds_qset_history(q, DDS_HISTORY_KEEP_LAST, t.depth);
    const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
    dds_qset_data_representation(q, 1, &xcdr1);
    const std::string name = std::string(t.name) == "tf" ? "rt/tf" : "rt/hapticd/" + device + "/" + t.name;
    const dds_entity_t topic = dds_create_topic(participant.get(), t.type, name.c_str(), q, nullptr);
    t.reader = dds_create_reader(participant.get(), topic, q, nullptr);
    dds_delete_qos(q);
    if (t.reader < 0) return 2;
  }
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::atof(argv[3]));
  while (std::chrono::steady_clock::now() < until) {
    for (Topic& t : topics) {
      void* samples[16] = {};
      dds_sample_info_t infos[16];
      const int n = dds_take(t.reader, samples, infos, 16, 16);  // loaned
      if (n > 0) {
        t.taken += n;
        dds_return_loan(t.reader, samples, n);
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  for (const Topic& t : topics) std::printf("%s %ld\n", t.name, t.taken);
  return 0;
}
