#include "bridge/device_link.hpp"

#include "group/group_stage.hpp"
#include "hapticd/dds/conversion.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {
namespace {

// The dds section's bounds; distances are taken from the device's base.
dds::CommandBounds bounds_of(const DdsSettings& settings, const Pose& base) {
  dds::CommandBounds b{settings.max_force_n,           settings.max_torque_nm,
                       settings.max_stiffness_n_per_m, settings.max_rotational_stiffness_n_m_per_rad,
                       settings.max_damping_n_s_per_m, settings.max_rotational_damping_n_m_s,
                       settings.max_distance_m,        {base.position.x(), base.position.y(), base.position.z()},
                       settings.max_speed_m_s,         settings.max_angular_speed_rad_s};
  return b;
}

}  // namespace

DeviceLink::DeviceLink(std::size_t i, DeviceSession* s, const DdsSettings& settings)
    : index(i),
      device(&s->requests()),
      status(&s->status()),
      gate(bounds_of(settings, s->description().base_pose), settings.max_sample_age_s) {}

DeviceLinks::DeviceLinks(const std::vector<DeviceSession*>& sessions, const std::vector<GroupStage*>& stages,
                         const DdsSettings& settings) {
  for (DeviceSession* s : sessions) links_.push_back(std::make_unique<DeviceLink>(links_.size(), s, settings));
  for (GroupStage* g : stages) {
    GroupLink group{g->name(), g, {}, 0};
    for (const DeviceSession* member : g->devices())
      for (const auto& l : links_)
        if (l->status == &member->status()) group.members.push_back(l->index);
    groups_.push_back(std::move(group));
  }
}

GroupLink* DeviceLinks::find_group(std::string_view group) noexcept {
  for (GroupLink& g : groups_)
    if (g.name == group) return &g;
  return nullptr;
}

DeviceLink* DeviceLinks::find(std::string_view device) noexcept {
  for (auto& l : links_)
    if (l->device->name() == device) return l.get();
  return nullptr;
}

dds_topic_filter DeviceLinks::command_filter() noexcept {
  return dds_topic_filter{DDS_TOPIC_FILTER_SAMPLE_ARG, {.sample_arg = &DeviceLinks::command_for_us}, this};
}

dds_topic_filter DeviceLinks::request_filter() noexcept {
  return dds_topic_filter{DDS_TOPIC_FILTER_SAMPLE_ARG, {.sample_arg = &DeviceLinks::request_for_us}, this};
}

dds_topic_filter DeviceLinks::group_command_filter() noexcept {
  return dds_topic_filter{DDS_TOPIC_FILTER_SAMPLE_ARG, {.sample_arg = &DeviceLinks::group_command_for_us}, this};
}

bool DeviceLinks::group_command_for_us(const void* sample, void* self) {
  auto* links = static_cast<DeviceLinks*>(self);
  if (links->find_group(dds::text_of(static_cast<const hapticd_msg_GroupCommand*>(sample)->group)) != nullptr)
    return true;
  links->unknown_commands_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool DeviceLinks::command_for_us(const void* sample, void* self) {
  auto* links = static_cast<DeviceLinks*>(self);
  if (links->find(dds::text_of(static_cast<const hapticd_msg_EngineCommand*>(sample)->device)) != nullptr) return true;
  links->unknown_commands_.fetch_add(1, std::memory_order_relaxed);  // malformed (the IDL's reason 0)
  return false;
}

bool DeviceLinks::request_for_us(const void* sample, void* self) {
  auto* links = static_cast<DeviceLinks*>(self);
  const std::string_view target = dds::text_of(static_cast<const hapticd_msg_ControlRequest*>(sample)->device);
  // A device, a group ("*" for group requests: every device of every server) of this server.
  if (links->find(target) != nullptr || links->find_group(target) != nullptr || target == "*") return true;
  links->unknown_requests_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

}  // namespace hapticd::server
