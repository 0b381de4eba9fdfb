#pragma once
// The devices one loop thread drives and the group stages among them, and one cycle of them in phases, each for
// every device before the next (docs/architecture.md, "One cycle"). The executor's real-time loops (through
// LoopWork) and the in-process session's lockstep steps run the same function. Real-time safe.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "executor/loop_work.hpp"
#include "hapticd/cycle_time.hpp"

namespace hapticd::server {

class DeviceSession;
class DeviceCycleSink;
class GroupStage;

class LoopCycle final : public LoopWork {
 public:
  // stages: the group stages of the device groups among these devices (phase (b)); they outlive this.
  // sink (the recorder) takes each device's cycle, as `producer`; device_ids: each device's number in the
  // session (empty: its place here).
  LoopCycle(std::vector<DeviceSession*> devices, std::vector<GroupStage*> stages = {}, DeviceCycleSink* sink = nullptr,
            std::size_t producer = 0, std::vector<std::uint16_t> device_ids = {});

  // One cycle: (a) read and estimate, (b) the group stages, (c) the chains, (d) limit, write and record.
  void run_cycle(const CycleTime& cycle, double torque_scale, std::uint32_t consecutive_overruns,
                 std::int64_t lateness_ns) noexcept override;
  void activate() override;  // every device, in order
  void request_safe_stop() noexcept override;
  // Every device is at rest (its safe mode reached zero torque, or no fault).
  [[nodiscard]] bool at_rest() const noexcept override;
  // The group stages, then every device (whatever their plugins threw).
  void deactivate(std::vector<std::string>& warnings, std::vector<std::string>& plugin_errors) override;
  [[nodiscard]] std::vector<std::string> device_names() const override;

  [[nodiscard]] const std::vector<DeviceSession*>& devices() const noexcept { return devices_; }
  [[nodiscard]] const std::vector<GroupStage*>& stages() const noexcept { return stages_; }

 private:
  std::vector<DeviceSession*> devices_;
  std::vector<GroupStage*> stages_;
  DeviceCycleSink* sink_;
  std::size_t producer_;
  std::vector<std::uint16_t> device_ids_;
};

}  // namespace hapticd::server
