#pragma once
// One device group's stage: phase (b) of the cycle, after every device of the loop was read and estimated and
// before any chain runs (docs/architecture.md, "One cycle"). Here group-level logic sees the states of all the
// group's devices of the same instant: today the collision guards between each pair of its devices (clearance,
// repulsion, hard minimum).
// Real-time safe after construction.
#include <memory>
#include <string>
#include <vector>

#include "group/collision_guard.hpp"
#include "hapticd/cycle_time.hpp"

namespace hapticd::server {

class DeviceSession;

class GroupStage {
 public:
  // A guard for every pair of devices with robot models: it measures their clearance, repels them (when
  // repulsion.distance_m > 0), and trips both below min_distance_m (0: never). period_s: the loop's.
  GroupStage(std::string name, std::vector<DeviceSession*> devices, double min_distance_m,
             const RepulsionSettings& repulsion, double period_s);

  void run(const CycleTime& cycle) noexcept;

  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] const std::vector<DeviceSession*>& devices() const noexcept { return devices_; }
  [[nodiscard]] const std::vector<std::unique_ptr<CollisionGuard>>& guards() const noexcept { return guards_; }

 private:
  std::string name_;
  std::vector<DeviceSession*> devices_;
  std::vector<std::unique_ptr<CollisionGuard>> guards_;
};

}  // namespace hapticd::server
