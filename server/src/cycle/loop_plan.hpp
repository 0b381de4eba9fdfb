#pragma once
// Which loop drives which device: the session's loop drives every device not in a group with a loop of its own
// (`groups[i].loop`); each such group runs on a loop of its own, pinned to its CPU. In lockstep there is one loop
// (the virtual clock has no CPUs to spread over, and one thread keeps runs repeatable). The plan holds each loop's
// LoopCycle and hands the executor its loops.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "cycle/loop_cycle.hpp"
#include "executor/executor.hpp"

namespace hapticd::server {

class DeviceSession;
class DeviceCycleSink;
class GroupStage;

// A group whose devices run on a loop thread of their own (`groups[i].loop`).
struct SeparateLoop {
  std::string name;  // the group's
  std::vector<DeviceSession*> devices;
  int cpu = -1;  // -1: not pinned
};

class LoopPlan {
 public:
  // devices: every device, in the session's order (their numbers in the recording); stages: the device groups'
  // stages, each run by the loop that holds its devices; separate: the groups with a loop of their own (ignored in
  // lockstep); session_cpu: the session's loop's CPU (-1: not pinned); sink: the recorder (null: none), with a
  // producer for every loop; clock_device: for `clock: device`, the device whose ticks clock the loop it is in.
  LoopPlan(const std::vector<DeviceSession*>& devices, const std::vector<GroupStage*>& stages,
           const std::vector<SeparateLoop>& separate, bool lockstep, int session_cpu, DeviceCycleSink* sink = nullptr,
           const DeviceSession* clock_device = nullptr);

  // The loops for the executor: the session's first (when it has devices), then the groups'.
  [[nodiscard]] const std::vector<ExecutorLoop>& loops() const noexcept { return loops_; }
  // The number of the loop that drives `device`.
  [[nodiscard]] std::size_t loop_of(const DeviceSession* device) const noexcept;
  // How many loops a session with these separate loops runs (the recorder's producers).
  [[nodiscard]] static std::size_t count(const std::vector<SeparateLoop>& separate, bool lockstep) noexcept;

 private:
  std::vector<std::unique_ptr<LoopCycle>> cycles_;
  std::vector<ExecutorLoop> loops_;
};

}  // namespace hapticd::server
