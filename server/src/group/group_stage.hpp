#pragma once
// One device group's stage: phase (b) of the cycle, after every device of the loop was read and estimated and
// before any chain runs (docs/architecture.md, "One cycle"). Here group-level logic sees the states of all the
// group's devices of the same instant: today the collision guards between each pair of its devices (clearance,
// repulsion, hard minimum). After phase (d) it gathers its devices' snapshots of the cycle into one group
// snapshot (the DDS group state: every device's state from one cycle).
// Real-time safe after construction.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "group/collision_guard.hpp"
#include "hapticd/cycle_time.hpp"
#include "hapticd/group_model.hpp"
#include "hapticd/realtime/latest_value.hpp"
#include "loader/plugin_loader.hpp"
#include "loader/plugin_requests.hpp"
#include "session/device_snapshot.hpp"

namespace hapticd::server {

class DeviceSession;

// The most devices a group holds (the session file is checked against it; hapticd_msg::MAX_GROUP_DEVICES).
inline constexpr std::size_t kMaxGroupDevices = 8;

// Every device's snapshot of one cycle, in the group's order.
struct GroupSnapshot {
  std::uint64_t cycle = 0;
  std::int64_t time_ns = 0;
  double clearance_m = -1.0;  // the nearest pair's clearance this cycle (-1: not measured)
  std::size_t count = 0;
  std::array<DeviceSnapshot, kMaxGroupDevices> devices{};
};

class GroupStage {
 public:
  // A guard for every pair of devices with robot models: it measures their clearance, repels them (when
  // repulsion.distance_m > 0), and trips both below min_distance_m (0: never). period_s: the loop's.
  // own_loop: the group runs on a loop thread of its own (told to the group's description).
  GroupStage(std::string name, std::vector<DeviceSession*> devices, double min_distance_m,
             const RepulsionSettings& repulsion, double period_s, bool own_loop = false);

  void run(const CycleTime& cycle) noexcept;
  // Before the loop runs: the group's model (`groups[i].model`, bimanual coupling). It activates at the first
  // cycle all the group's devices run (again after a failure, once all are recovered); each cycle it answers a
  // force per handle, added to the device's group force. A model that fails, throws or answers a non-finite
  // force stops every device of the group (fault group_model).
  // Its run-time requests come through each of the group's devices ("group_model.<name>").
  void set_model(PluginInstance<GroupModel> model);
  [[nodiscard]] GroupModel* model() noexcept { return model_.object.get(); }
  // After the loop has ended (requests no longer reach the model). Returns what the group's model threw as it was
  // deactivated, empty if nothing (the caller goes on to disable the devices).
  [[nodiscard]] std::string deactivate();
  // After phase (d), at the cycles the devices publish snapshots: the group's snapshot of them.
  void publish_snapshot(const CycleTime& cycle) noexcept;
  // Before the loop runs: the devices' snapshot interval (0: never, the default).
  void set_snapshot_interval(std::uint64_t cycles) noexcept { snapshot_interval_ = cycles; }
  // Any thread, one reader: the newest group snapshot; false if none since the last take.
  bool take_snapshot(GroupSnapshot& out) noexcept { return snapshots_.take(out); }

  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] const std::vector<DeviceSession*>& devices() const noexcept { return devices_; }
  [[nodiscard]] const std::vector<std::unique_ptr<CollisionGuard>>& guards() const noexcept { return guards_; }
  [[nodiscard]] double min_distance_m() const noexcept { return min_distance_m_; }
  [[nodiscard]] double repulsion_distance_m() const noexcept { return repulsion_distance_m_; }
  [[nodiscard]] bool own_loop() const noexcept { return own_loop_; }

 private:
  std::string name_;
  std::vector<DeviceSession*> devices_;
  std::vector<std::unique_ptr<CollisionGuard>> guards_;
  void run_model(const CycleTime& cycle) noexcept;
  void fail_model(const CycleTime& cycle, const char* reason) noexcept;
  PluginInstance<GroupModel> model_;
  SharedPlugin model_requests_;  // the devices' way to the model's requests
  bool model_active_ = false;
  std::array<GroupHand, kMaxGroupDevices> hands_{};
  std::array<Eigen::Vector3d, kMaxGroupDevices> model_forces_{};
  double min_distance_m_;
  double repulsion_distance_m_;
  bool own_loop_;
  std::uint64_t snapshot_interval_ = 0;
  GroupSnapshot snapshot_;  // loop thread
  realtime::LatestValue<GroupSnapshot> snapshots_;
};

}  // namespace hapticd::server
