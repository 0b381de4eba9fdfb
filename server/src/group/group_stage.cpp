#include "group/group_stage.hpp"

#include "hapticd/demand.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

GroupStage::GroupStage(std::string name, std::vector<DeviceSession*> devices, double min_distance_m,
                       const RepulsionSettings& repulsion, double period_s, bool own_loop)
    : name_(std::move(name)),
      devices_(std::move(devices)),
      min_distance_m_(min_distance_m),
      repulsion_distance_m_(repulsion.distance_m),
      own_loop_(own_loop) {
  HAPTICD_DEMAND(devices_.size() <= kMaxGroupDevices);  // the session file is checked against it
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

void GroupStage::publish_snapshot(const CycleTime& cycle) noexcept {
  if (snapshot_interval_ == 0 || cycle.index % snapshot_interval_ != 0) return;
  GroupSnapshot& s = snapshot_;
  s.cycle = cycle.index;
  s.time_ns = cycle.time_ns;
  s.clearance_m = -1.0;
  for (const auto& guard : guards_) {
    const double d = guard->latest_distance();
    if (d < 1e9 && (s.clearance_m < 0.0 || d < s.clearance_m)) s.clearance_m = d;
  }
  s.count = devices_.size();
  for (std::size_t k = 0; k < devices_.size(); ++k) s.devices[k] = devices_[k]->published_snapshot();
  snapshots_.publish(s);
}

}  // namespace hapticd::server
