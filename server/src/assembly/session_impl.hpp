#pragma once
// What a Session (hapticd/server/session.hpp) holds: the configuration, the plugins, the device sessions and
// the loop cycle that runs them. The server's own tests reach the device sessions through it (to drive one
// device's phases alone, or to run the real executor over them); everything else uses the public API.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "config/session_config.hpp"
#include "cycle/loop_cycle.hpp"
#include "cycle/loop_plan.hpp"
#include "executor/cycle_statistics.hpp"
#include "executor/executor.hpp"
#include "group/group_stage.hpp"
#include "hapticd/server/session.hpp"
#include "loader/plugin_loader.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

struct Session::Impl {
  SessionConfig config;
  std::unique_ptr<PluginLoader> loader;
  std::vector<std::unique_ptr<DeviceSession>> devices;
  std::vector<std::unique_ptr<GroupStage>> stages;  // the device groups' stages (`groups`)
  std::unique_ptr<LoopCycle> cycle;                 // every device on one thread: lockstep
  std::int64_t period_ns = 0;
  std::uint64_t next_cycle = 0;
  bool activated = false;
  bool stopped = false;
  CycleStatistics statistics;
  // What plugins threw as they were deactivated ("device 'd': scheme 's', controller 'c': what"): reported
  // by stop().
  std::vector<std::string> plugin_errors;

  // Deactivates the schemes the loop has left, keeping what their plugins threw.
  void service_devices();

  // Throws std::out_of_range naming the device.
  [[nodiscard]] DeviceSession& device(std::string_view name) const;
  [[nodiscard]] std::vector<DeviceSession*> device_pointers() const;
  [[nodiscard]] std::vector<GroupStage*> stage_pointers() const;
  // The executor's settings for this session's server section, never asking for SCHED_FIFO or locked memory
  // (for tests that run the real loop over the devices instead of stepping).
  [[nodiscard]] ExecutorSettings executor_settings() const;
  // The loops of this session's devices and groups (in lockstep one), for those tests; sink: a recorder.
  [[nodiscard]] LoopPlan loop_plan(DeviceCycleSink* sink = nullptr) const;
};

}  // namespace hapticd::server
