#pragma once
// One ROS 2 topic as ROS 2's middlewares make it (docs/ros2.md, "On the wire"): the DDS topic "rt" + its ROS name
// (ROS 2 design, "Topic and Service name mapping to DDS"), the type's DDS name from its descriptor
// (geometry_msgs::msg::dds_::PoseStamped_), samples in XCDR1 as rmw_cyclonedds writes them, and one of ROS 2's QoS
// profiles (rmw/qos_profiles.h; tf2_ros's and robot_state_publisher's).
#include <dds/dds.h>

#include <string>
#include <string_view>

#include "hapticd/dds/entity.hpp"
#include "hapticd/dds/topics.hpp"

namespace hapticd::server::ros2 {

enum class Profile : std::uint8_t {
  sensor_data,  // rmw_qos_profile_sensor_data: best effort, volatile, keep last 5 (states)
  commands,     // rmw_qos_profile_default: reliable, volatile, keep last 10 (commands)
  tf,           // tf2_ros's broadcaster: reliable, volatile, keep last 100 (/tf)
  latched,      // robot_state_publisher's robot_description: reliable, transient local, keep last 1
};
[[nodiscard]] dds::Qos qos(Profile profile);
// "rt/hapticd/vishard3/pose" of "/hapticd/vishard3/pose".
[[nodiscard]] std::string dds_topic_name(std::string_view ros_name);

// A topic, reader or writer of the door's (the DDS names as given: "rt/...", "rq/...Request", "rr/...Reply"). Throw
// dds::Error starting with `what` when Cyclone refuses.
[[nodiscard]] dds::Entity make_topic(dds_entity_t participant, const std::string& dds_name,
                                     const dds_topic_descriptor_t* type, const dds_qos_t* qos, const std::string& what);
[[nodiscard]] dds::Entity make_reader(dds_entity_t participant, const dds::Entity& topic, const dds_qos_t* qos,
                                      const std::string& what);
[[nodiscard]] dds::Entity make_writer(dds_entity_t participant, const dds::Entity& topic, const dds_qos_t* qos,
                                      const std::string& what);

class Writer {
 public:
  // Throws dds::Error naming the topic when Cyclone refuses it.
  Writer(dds_entity_t participant, const std::string& ros_name, const dds_topic_descriptor_t* type, Profile profile);
  // `sample`: the descriptor's C type. A failed write returns false (the door counts it).
  bool write(const void* sample, dds_time_t stamp) const noexcept {
    return dds_write_ts(writer_.get(), sample, stamp) == DDS_RETCODE_OK;
  }
  [[nodiscard]] dds_entity_t get() const noexcept { return writer_.get(); }

 private:
  dds::Entity topic_, writer_;
};

}  // namespace hapticd::server::ros2
