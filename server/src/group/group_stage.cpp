#include "group/group_stage.hpp"

#include "session/device_session.hpp"

namespace hapticd::server {

GroupStage::GroupStage(std::string name, std::vector<DeviceSession*> devices, double min_distance_m,
                       const RepulsionSettings& repulsion, double period_s)
    : name_(std::move(name)), devices_(std::move(devices)) {
  const auto has_geometry = [](const DeviceSession* d) { return d->chain().robot_model != nullptr; };
  for (std::size_t i = 0; i < devices_.size(); ++i)
    for (std::size_t j = i + 1; j < devices_.size(); ++j)
      if (has_geometry(devices_[i]) && has_geometry(devices_[j]))
        guards_.push_back(
            std::make_unique<CollisionGuard>(*devices_[i], *devices_[j], min_distance_m, repulsion, period_s));
}

void GroupStage::run(const CycleTime& cycle) noexcept {
  for (const auto& guard : guards_) guard->run(cycle);
}

}  // namespace hapticd::server
