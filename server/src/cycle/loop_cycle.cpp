#include "cycle/loop_cycle.hpp"

#include <algorithm>

#include "cycle/device_cycle_sink.hpp"
#include "executor/loop_clock.hpp"
#include "group/group_stage.hpp"
#include "hapticd/demand.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

LoopCycle::LoopCycle(std::vector<DeviceSession*> devices, std::vector<GroupStage*> stages, DeviceCycleSink* sink,
                     std::size_t producer, std::vector<std::uint16_t> device_ids)
    : devices_(std::move(devices)),
      stages_(std::move(stages)),
      sink_(sink),
      producer_(producer),
      device_ids_(std::move(device_ids)) {
  if (device_ids_.empty())
    for (std::size_t d = 0; d < devices_.size(); ++d) device_ids_.push_back(static_cast<std::uint16_t>(d));
  HAPTICD_DEMAND(device_ids_.size() == devices_.size());
  HAPTICD_DEMAND(sink_ == nullptr || producer_ < sink_->producers());
  if (sink_ != nullptr)
    for (DeviceSession* s : devices_) s->set_snapshot_every_cycle(true);  // the record is built from it
}

void LoopCycle::run_cycle(const CycleTime& cycle, double torque_scale, std::uint32_t consecutive_overruns,
                          std::int64_t lateness_ns) noexcept {
  const std::int64_t start_ns = sink_ != nullptr ? monotonic_now_ns() : 0;
  // (a) read and estimate: every device's state of this instant, before any chain runs;
  for (DeviceSession* s : devices_) s->read_and_estimate(cycle, consecutive_overruns, lateness_ns);
  // (b) the group stages, where group-level logic sees the estimated states of all devices of its group (the
  //     collision guards between a group's devices);
  for (GroupStage* g : stages_) g->run(cycle);
  // (c) the chains: virtual model -> inverse kinematics -> controller;
  for (DeviceSession* s : devices_) s->run_chain(cycle);
  // (d) limit and write, then record;
  for (std::size_t d = 0; d < devices_.size(); ++d) {
    devices_[d]->limit_and_write(cycle, torque_scale);
    if (sink_ != nullptr)
      sink_->device_written(producer_, *devices_[d], device_ids_[d], cycle, lateness_ns, monotonic_now_ns() - start_ns);
  }
  // then each group's snapshot: its devices' states of this cycle, together (the DDS group state).
  for (GroupStage* g : stages_) g->publish_snapshot(cycle);
}

void LoopCycle::activate() {
  for (DeviceSession* d : devices_) d->activate();
}

void LoopCycle::request_safe_stop() noexcept {
  for (DeviceSession* d : devices_) d->requests().safe_stop();
}

bool LoopCycle::at_rest() const noexcept {
  return std::all_of(devices_.begin(), devices_.end(), [](const DeviceSession* s) { return s->status().at_rest(); });
}

void LoopCycle::deactivate(std::vector<std::string>& warnings, std::vector<std::string>& plugin_errors) {
  for (GroupStage* g : stages_)
    if (std::string error = g->deactivate(); !error.empty())
      plugin_errors.push_back("group '" + g->name() + "': " + error);
  for (DeviceSession* s : devices_) {
    s->deactivate();  // whatever its plugins threw
    if (!s->disable_error().empty())
      warnings.push_back("device '" + s->name() + "': " + s->disable_error() + " (its drives may still be on)");
    for (std::string& e : s->take_plugin_errors()) plugin_errors.push_back("device '" + s->name() + "': " + e);
  }
}

std::vector<std::string> LoopCycle::device_names() const {
  std::vector<std::string> names;
  for (const DeviceSession* d : devices_) names.push_back(d->name());
  return names;
}

}  // namespace hapticd::server
