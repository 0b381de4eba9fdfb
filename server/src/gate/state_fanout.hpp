#pragma once
// The gate's output to every door (Door's sinks): each device's state (the publisher thread, woken by the loop
// after each cycle, takes the snapshots from their lock-free hand-off, makes the data model's message once and
// hands both to each door in turn) and the events it reveals (events_between), the descriptions, fault reports
// (the monitor's thread) and telemetry (the service thread).
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "executor/executor.hpp"
#include "gate/device_gate.hpp"
#include "gate/door.hpp"
#include "gate/event_fanout.hpp"
#include "gate/messages.hpp"
#include "group/group_stage.hpp"

namespace hapticd::server {

class StateFanout {
 public:
  StateFanout(DeviceGates& devices, EventFanout& events, double rate_hz, std::uint64_t snapshot_interval);

  // Before the threads start: where the live statistics of the loop that drives `device` are (the executor's).
  void set_loop_statistics(std::size_t device, const LiveLoopStatistics* live) noexcept { live_[device] = live; }
  // Before the threads start: the doors, in the order each state reaches them (the teleoperation link first:
  // its round trip is the loop's; then the engine socket, whose hand-off returns at once; DDS's write last).
  void set_doors(std::vector<Door*> doors) { doors_ = std::move(doors); }

  // Publisher thread (and once more at the end): the new snapshot of every device as a state, and its events.
  // A device with nothing new has its last state repeated now and then, for readers that matched after it.
  void publish_states();
  // Any thread: a device's description (with its start pose once the loop has run).
  void publish_description(std::size_t device);
  // Any thread: a group's description.
  void publish_group_description(const GroupGate& group);
  // Any thread: a fault report.
  void publish_fault_report(std::size_t device, const FaultReport& report);
  // Service thread: every device's telemetry.
  void publish_telemetry();

 private:
  struct Published {  // per device, publisher thread (start_pose: under description_mutex)
    DeviceSnapshot snapshot;
    PublishedView view;
    hapticd_msg_DeviceState last{};
    std::int64_t last_write_ns = 0;
    std::optional<Pose> start_pose;
    std::vector<std::string> scheme_names;
  };
  [[nodiscard]] hapticd_msg_LoopSummary loop_summary(std::size_t device) const noexcept;
  // What a device's state says besides its snapshot (owner: the claim's client id).
  [[nodiscard]] StateLabels labels_of(std::size_t device, const DeviceSnapshot& s, const std::string& owner) const;
  // Publisher thread: each group's newest snapshot as one group state.
  void publish_group_states();

  DeviceGates& devices_;
  EventFanout& events_;
  double rate_hz_;
  std::uint64_t snapshot_interval_;
  std::vector<const LiveLoopStatistics*> live_;  // per device: its loop's
  std::vector<Door*> doors_;
  std::vector<Published> published_;
  std::unique_ptr<GroupSnapshot> group_snapshot_;                        // publisher thread (8 device snapshots)
  std::vector<std::unique_ptr<hapticd_msg_GroupState>> group_messages_;  // per group, the last (about 7 kB)
  std::vector<std::int64_t> group_written_ns_;                           // ... and when it was written
  std::mutex description_mutex_;
};

}  // namespace hapticd::server
