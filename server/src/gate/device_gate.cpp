#include "gate/device_gate.hpp"

#include "group/group_stage.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {
namespace {

// The gate's bounds; distances are taken from the device's base.
dds::CommandBounds bounds_of(const GateSettings& settings, const Pose& base) {
  dds::CommandBounds b{settings.max_force_n,           settings.max_torque_nm,
                       settings.max_stiffness_n_per_m, settings.max_rotational_stiffness_n_m_per_rad,
                       settings.max_damping_n_s_per_m, settings.max_rotational_damping_n_m_s,
                       settings.max_distance_m,        {base.position.x(), base.position.y(), base.position.z()},
                       settings.max_speed_m_s,         settings.max_angular_speed_rad_s};
  return b;
}

}  // namespace

DeviceGate::DeviceGate(std::size_t i, DeviceSession* s, const GateSettings& settings)
    : index(i),
      device(&s->requests()),
      status(&s->status()),
      gate(bounds_of(settings, s->description().base_pose), settings.max_sample_age_s) {}

DeviceGates::DeviceGates(const std::vector<DeviceSession*>& sessions, const std::vector<GroupStage*>& stages,
                         const GateSettings& settings) {
  for (DeviceSession* s : sessions) devices_.push_back(std::make_unique<DeviceGate>(devices_.size(), s, settings));
  for (GroupStage* g : stages) {
    GroupGate group{g->name(), g, {}, 0};
    for (const DeviceSession* member : g->devices())
      for (const auto& d : devices_)
        if (d->status == &member->status()) group.members.push_back(d->index);
    groups_.push_back(std::move(group));
  }
}

const GroupGate* DeviceGates::find_group(std::string_view group) const noexcept {
  for (const GroupGate& g : groups_)
    if (g.name == group) return &g;
  return nullptr;
}
GroupGate* DeviceGates::find_group(std::string_view group) noexcept {
  return const_cast<GroupGate*>(static_cast<const DeviceGates*>(this)->find_group(group));
}

const DeviceGate* DeviceGates::find(std::string_view device) const noexcept {
  for (const auto& d : devices_)
    if (d->device->name() == device) return d.get();
  return nullptr;
}
DeviceGate* DeviceGates::find(std::string_view device) noexcept {
  return const_cast<DeviceGate*>(static_cast<const DeviceGates*>(this)->find(device));
}

bool DeviceGates::request_target(std::string_view target) const noexcept {
  return find(target) != nullptr || find_group(target) != nullptr || target == "*";
}

}  // namespace hapticd::server
