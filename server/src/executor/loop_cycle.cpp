#include "executor/loop_cycle.hpp"

#include <algorithm>

#include "executor/loop_clock.hpp"
#include "group/group_stage.hpp"
#include "hapticd/demand.hpp"
#include "recorder/recorder.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

LoopCycle::LoopCycle(std::vector<DeviceSession*> devices, Recorder* recorder, std::vector<GroupStage*> stages,
                     std::vector<std::uint16_t> record_ids, std::size_t producer)
    : devices_(std::move(devices)),
      recorder_(recorder),
      stages_(std::move(stages)),
      record_ids_(std::move(record_ids)),
      producer_(producer) {
  if (record_ids_.empty())
    for (std::size_t d = 0; d < devices_.size(); ++d) record_ids_.push_back(static_cast<std::uint16_t>(d));
  HAPTICD_DEMAND(record_ids_.size() == devices_.size());
  HAPTICD_DEMAND(recorder_ == nullptr || producer_ < recorder_->producers());
  if (recorder_ != nullptr)
    for (DeviceSession* s : devices_) s->set_snapshot_every_cycle(true);  // the record is built from it
}

void LoopCycle::run_cycle(const CycleTime& cycle, double torque_scale, std::uint32_t consecutive_overruns,
                          std::int64_t lateness_ns) noexcept {
  const std::int64_t start_ns = recorder_ != nullptr ? monotonic_now_ns() : 0;
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
    if (recorder_ != nullptr) {
      fill_cycle_record(record_, *devices_[d], record_ids_[d], cycle, lateness_ns, monotonic_now_ns() - start_ns);
      recorder_->record(producer_, record_);
    }
  }
  // then each group's snapshot: its devices' states of this cycle, together (the DDS group state).
  for (GroupStage* g : stages_) g->publish_snapshot(cycle);
}

bool LoopCycle::at_rest() const noexcept {
  return std::all_of(devices_.begin(), devices_.end(), [](const DeviceSession* s) { return s->at_rest(); });
}

}  // namespace hapticd::server
