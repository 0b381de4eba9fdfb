#pragma once
// The devices one loop thread drives, and one cycle of them in phases, each for every device before the next
// (docs/architecture.md, "One cycle"). The executor's real-time loops and the in-process session's lockstep
// steps run the same function. Real-time safe.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hapticd/cycle_time.hpp"
#include "recorder/cycle_record.hpp"

namespace hapticd::server {

class DeviceSession;
class GroupStage;
class Recorder;

class LoopCycle {
 public:
  // stages: the group stages of the device groups among these devices (phase (b)); they outlive this.
  // record_ids: each device's number in the recording (empty: its place here); producer: this loop's ring in the
  // recorder.
  LoopCycle(std::vector<DeviceSession*> devices, Recorder* recorder, std::vector<GroupStage*> stages = {},
            std::vector<std::uint16_t> record_ids = {}, std::size_t producer = 0);

  // One cycle: (a) read and estimate, (b) the group stages, (c) the chains, (d) limit, write and record.
  // torque_scale ramps the output down at a planned end; consecutive_overruns and lateness_ns feed the
  // devices' loop watchdogs.
  void run_cycle(const CycleTime& cycle, double torque_scale, std::uint32_t consecutive_overruns,
                 std::int64_t lateness_ns) noexcept;

  [[nodiscard]] const std::vector<DeviceSession*>& devices() const noexcept { return devices_; }
  [[nodiscard]] const std::vector<GroupStage*>& stages() const noexcept { return stages_; }
  // Every device is at rest (its safe mode reached zero torque, or no fault).
  [[nodiscard]] bool at_rest() const noexcept;

 private:
  std::vector<DeviceSession*> devices_;
  Recorder* recorder_;
  std::vector<GroupStage*> stages_;
  std::vector<std::uint16_t> record_ids_;
  std::size_t producer_;
  CycleRecord record_;  // scratch for the recorder (not on the loop's stack: 1.6 kB)
};

}  // namespace hapticd::server
