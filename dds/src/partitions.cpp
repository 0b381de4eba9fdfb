// The partitions of a device's requests and commands (endpoints.hpp, docs/dds-interface.md "Partitions").
#include <vector>

#include "hapticd/dds/endpoints.hpp"

namespace hapticd::dds {

std::string target_partition(std::string_view target) {
  return target == "*" ? std::string("hapticd.all") : "hapticd." + std::string(target);
}

namespace {
Qos partition_qos(const std::vector<std::string>& partitions) {
  Qos q(dds_create_qos());
  std::vector<const char*> names;
  for (const auto& p : partitions) names.push_back(p.c_str());
  dds_qset_partition(q.get(), static_cast<uint32_t>(names.size()), names.data());
  return q;
}
}  // namespace

Entity publisher_in(const Participant& participant, const std::vector<std::string>& partitions) {
  const Qos q = partition_qos(partitions);
  return Entity(check(dds_create_publisher(participant.get(), q.get(), nullptr), "cannot create a DDS publisher"));
}

Entity subscriber_in(const Participant& participant, const std::vector<std::string>& partitions) {
  const Qos q = partition_qos(partitions);
  return Entity(check(dds_create_subscriber(participant.get(), q.get(), nullptr), "cannot create a DDS subscriber"));
}

}  // namespace hapticd::dds
