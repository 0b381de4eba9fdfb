#pragma once
// The devices one loop drives, and one cycle of them in phases, each for every device before the next
// (docs/architecture.md, "One cycle"). The executor's real-time loop and the in-process session's lockstep
// steps run the same function. Real-time safe.
#include <cstdint>
#include <vector>

#include "hapticd/cycle_time.hpp"

namespace hapticd::server {

class DeviceSession;
class GroupStage;
class Recorder;

class DeviceGroup {
 public:
  // stages: the group stages of the device groups among these devices (phase (b)); they outlive this.
  DeviceGroup(std::vector<DeviceSession*> devices, Recorder* recorder, std::vector<GroupStage*> stages = {}) noexcept
      : devices_(std::move(devices)), recorder_(recorder), stages_(std::move(stages)) {}

  // One cycle: (a) read and estimate, (b) the group stage, (c) the chains, (d) limit, write and record.
  // torque_scale ramps the output down at a planned end; consecutive_overruns and lateness_ns feed the
  // devices' loop watchdogs.
  void run_cycle(const CycleTime& cycle, double torque_scale, std::uint32_t consecutive_overruns,
                 std::int64_t lateness_ns) noexcept;

  [[nodiscard]] const std::vector<DeviceSession*>& devices() const noexcept { return devices_; }
  // Every device is at rest (its safe mode reached zero torque, or no fault).
  [[nodiscard]] bool at_rest() const noexcept;

 private:
  std::vector<DeviceSession*> devices_;
  Recorder* recorder_;
  std::vector<GroupStage*> stages_;
};

}  // namespace hapticd::server
