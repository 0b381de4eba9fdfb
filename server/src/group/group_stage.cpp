#include "group/group_stage.hpp"

#include "hapticd/demand.hpp"
#include "loader/plugin_deactivation.hpp"
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
  if (model_.object) run_model(cycle);
}

void GroupStage::set_model(PluginInstance<GroupModel> model) {
  model_ = std::move(model);
  {
    std::lock_guard lock(model_requests_.requests);
    model_requests_.target.emplace(request_target(model_));
  }
  for (DeviceSession* d : devices_) d->requests().set_group_model(&model_requests_);
}

void GroupStage::run_model(const CycleTime& cycle) noexcept {
  const std::size_t n = devices_.size();
  bool all_running = true;
  for (std::size_t k = 0; k < n; ++k) {
    const ChainState& c = devices_[k]->chain_state();
    hands_[k] =
        GroupHand{c.handle_pose, c.handle_twist, c.operator_wrench, devices_[k]->status().fault() == DeviceFault::none};
    all_running = all_running && hands_[k].running;
  }
  if (!model_active_ && !all_running) return;  // it starts (again) once every hand is there
  const std::span<const GroupHand> hands(hands_.data(), n);
  const std::span<Eigen::Vector3d> forces(model_forces_.data(), n);
  Outcome outcome;
  try {
    if (!model_active_) {
      if (const Outcome o = model_->activate(hands); !o.ok()) return fail_model(cycle, o.reason);
      model_active_ = true;
    }
    outcome = model_->update(cycle, hands, forces);
  } catch (...) {
    return fail_model(cycle, "the group's model threw an exception");
  }
  if (!outcome.ok()) return fail_model(cycle, outcome.reason);
  for (std::size_t k = 0; k < n; ++k)
    if (!model_forces_[k].allFinite()) return fail_model(cycle, "the group's model answered a non-finite force");
  for (std::size_t k = 0; k < n; ++k)
    if (hands_[k].running) devices_[k]->add_group_force(model_forces_[k]);
}

void GroupStage::fail_model(const CycleTime& cycle, const char* reason) noexcept {
  model_active_ = false;
  for (DeviceSession* d : devices_)
    if (d->status().fault() == DeviceFault::none) d->raise_group_fault(DeviceFault::group_model, cycle, reason);
}

std::string GroupStage::deactivate() {
  {
    std::lock_guard lock(model_requests_.requests);  // waits for a request being served
    model_requests_.target.reset();
  }
  model_active_ = false;
  return deactivate_plugin(model_, "group model");
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
