#include "doors/ros2/ros2_topic.hpp"

namespace hapticd::server::ros2 {

dds::Qos qos(Profile profile) {
  dds::Qos q(dds_create_qos());
  switch (profile) {
    case Profile::sensor_data:
      dds_qset_reliability(q.get(), DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, 5);
      break;
    case Profile::commands:
      dds_qset_reliability(q.get(), DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
      dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, 10);
      break;
    case Profile::tf:
      dds_qset_reliability(q.get(), DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
      dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, 100);
      break;
    case Profile::latched:
      dds_qset_reliability(q.get(), DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
      dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, 1);
      dds_qset_durability(q.get(), DDS_DURABILITY_TRANSIENT_LOCAL);
      break;
  }
  if (profile != Profile::latched) dds_qset_durability(q.get(), DDS_DURABILITY_VOLATILE);
  // XCDR1, as rmw_cyclonedds and rmw_fastrtps write (ROS 2 Jazzy and before).
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(q.get(), 1, &xcdr1);
  return q;
}

std::string dds_topic_name(std::string_view ros_name) { return "rt" + std::string(ros_name); }

dds::Entity make_topic(dds_entity_t participant, const std::string& dds_name, const dds_topic_descriptor_t* type,
                       const dds_qos_t* qos, const std::string& what) {
  return dds::Entity(dds::check(dds_create_topic(participant, type, dds_name.c_str(), qos, nullptr), what.c_str()));
}
dds::Entity make_reader(dds_entity_t participant, const dds::Entity& topic, const dds_qos_t* qos,
                        const std::string& what) {
  return dds::Entity(dds::check(dds_create_reader(participant, topic.get(), qos, nullptr), what.c_str()));
}
dds::Entity make_writer(dds_entity_t participant, const dds::Entity& topic, const dds_qos_t* qos,
                        const std::string& what) {
  return dds::Entity(dds::check(dds_create_writer(participant, topic.get(), qos, nullptr), what.c_str()));
}

Writer::Writer(dds_entity_t participant, const std::string& ros_name, const dds_topic_descriptor_t* type,
               Profile profile) {
  const dds::Qos q = qos(profile);
  const std::string what = "cannot create the ROS 2 topic " + ros_name;
  topic_ = make_topic(participant, dds_topic_name(ros_name), type, q.get(), what);
  writer_ = make_writer(participant, topic_, q.get(), what);
}

}  // namespace hapticd::server::ros2
