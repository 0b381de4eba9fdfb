#include "cycle/loop_plan.hpp"

#include <algorithm>

#include "group/group_stage.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

LoopPlan::LoopPlan(const std::vector<DeviceSession*>& devices, const std::vector<GroupStage*>& stages,
                   const std::vector<SeparateLoop>& separate, bool lockstep, int session_cpu, DeviceCycleSink* sink,
                   const DeviceSession* clock_device) {
  std::vector<const SeparateLoop*> own;  // lockstep runs every device on one loop
  if (!lockstep)
    for (const SeparateLoop& l : separate)
      if (!l.devices.empty()) own.push_back(&l);
  const auto loop_of = [&](const DeviceSession* d) -> std::size_t {  // 0: the session's, k + 1: own[k]
    for (std::size_t k = 0; k < own.size(); ++k)
      if (std::find(own[k]->devices.begin(), own[k]->devices.end(), d) != own[k]->devices.end()) return k + 1;
    return 0;
  };
  struct Share {
    std::vector<DeviceSession*> devices;
    std::vector<std::uint16_t> ids;
    std::vector<GroupStage*> stages;
  };
  std::vector<Share> shares(own.size() + 1);
  for (std::size_t i = 0; i < devices.size(); ++i) {
    Share& share = shares[loop_of(devices[i])];
    share.devices.push_back(devices[i]);
    share.ids.push_back(static_cast<std::uint16_t>(i));
  }
  for (GroupStage* g : stages) shares[g->devices().empty() ? 0 : loop_of(g->devices().front())].stages.push_back(g);
  for (std::size_t k = 0; k < shares.size(); ++k) {
    if (k == 0 && shares[0].devices.empty() && !own.empty()) continue;  // every device is in a loop of its own
    const std::size_t producer = cycles_.size();
    cycles_.push_back(std::make_unique<LoopCycle>(shares[k].devices, shares[k].stages, sink, producer, shares[k].ids));
    const auto& mine = shares[k].devices;
    DeviceClock* clock = nullptr;
    if (clock_device != nullptr && !lockstep && std::find(mine.begin(), mine.end(), clock_device) != mine.end())
      clock = clock_device->chain().device->clock();
    loops_.push_back(ExecutorLoop{k == 0 ? std::string("session") : own[k - 1]->name,
                                  k == 0 ? session_cpu : own[k - 1]->cpu, cycles_.back().get(), clock});
  }
}

std::size_t LoopPlan::loop_of(const DeviceSession* device) const noexcept {
  for (std::size_t k = 0; k < cycles_.size(); ++k) {
    const auto& d = cycles_[k]->devices();
    if (std::find(d.begin(), d.end(), device) != d.end()) return k;
  }
  return 0;
}

std::size_t LoopPlan::count(const std::vector<SeparateLoop>& separate, bool lockstep) noexcept {
  if (lockstep) return 1;
  return 1 + static_cast<std::size_t>(std::count_if(separate.begin(), separate.end(),
                                                    [](const SeparateLoop& l) { return !l.devices.empty(); }));
}

}  // namespace hapticd::server
