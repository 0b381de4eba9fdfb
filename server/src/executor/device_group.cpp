#include "executor/device_group.hpp"

#include <algorithm>

#include "group/group_stage.hpp"
#include "recorder/recorder.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

void DeviceGroup::run_cycle(const CycleTime& cycle, double torque_scale, std::uint32_t consecutive_overruns,
                            std::int64_t lateness_ns) noexcept {
  // (a) read and estimate: every device's state of this instant, before any chain runs;
  for (DeviceSession* s : devices_) s->read_and_estimate(cycle, consecutive_overruns, lateness_ns);
  // (b) the group stages, where group-level logic sees the estimated states of all devices of its group (the
  //     collision guards between a group's devices);
  for (GroupStage* g : stages_) g->run(cycle);
  // (c) the chains: virtual model -> inverse kinematics -> controller;
  for (DeviceSession* s : devices_) s->run_chain(cycle);
  // (d) limit and write, then record.
  for (std::size_t d = 0; d < devices_.size(); ++d) {
    devices_[d]->limit_and_write(cycle, torque_scale);
    if (recorder_ != nullptr)
      recorder_->record(cycle, static_cast<std::uint16_t>(d), devices_[d]->state(), devices_[d]->command());
  }
}

bool DeviceGroup::at_rest() const noexcept {
  return std::all_of(devices_.begin(), devices_.end(), [](const DeviceSession* s) { return s->at_rest(); });
}

}  // namespace hapticd::server
