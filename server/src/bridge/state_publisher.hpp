#pragma once
// The bridge's publishing side: each device's state (the publisher thread, woken by the loop after each cycle,
// takes the snapshots from their lock-free hand-off) and the events it reveals (events_between), the
// descriptions, fault reports (the monitor's thread) and telemetry (the receiver thread).
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "bridge/dds_endpoints.hpp"
#include "bridge/device_link.hpp"
#include "bridge/event_sender.hpp"
#include "bridge/messages.hpp"
#include "executor/executor.hpp"
#include "group/group_stage.hpp"

namespace hapticd::server {

class EngineSocket;
class TeleopLink;

class StatePublisher {
 public:
  StatePublisher(DdsEndpoints& dds, DeviceLinks& links, EventSender& events, double rate_hz,
                 std::uint64_t snapshot_interval);

  // Before the threads start: where the live statistics of the loop that drives `device` are (the executor's).
  void set_loop_statistics(std::size_t device, const LiveLoopStatistics* live) noexcept { live_[device] = live; }
  // Before the threads start: the engine socket, which sends each state to its clients too (nullptr: none).
  void set_engine_socket(EngineSocket* socket) noexcept { socket_ = socket; }
  // Before the threads start: the teleoperation link, which runs with each state of its device (nullptr: none).
  void set_teleop_link(TeleopLink* link) noexcept { link_ = link; }

  // Publisher thread (and once more at the end): the new snapshot of every device as a state, and its events.
  // A device with nothing new has its last state repeated now and then, for readers that matched after it.
  void publish_states();
  // Any thread: a device's description (with its start pose once the loop has run).
  void publish_description(std::size_t device);
  // Any thread: a group's description.
  void publish_group_description(const GroupLink& group);
  // Any thread: a fault report.
  void publish_fault_report(std::size_t device, const FaultReport& report);
  // Receiver thread: every device's telemetry.
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

  DdsEndpoints& dds_;
  DeviceLinks& links_;
  EventSender& events_;
  double rate_hz_;
  std::uint64_t snapshot_interval_;
  std::vector<const LiveLoopStatistics*> live_;  // per device: its loop's
  EngineSocket* socket_ = nullptr;
  TeleopLink* link_ = nullptr;
  std::vector<Published> published_;
  std::unique_ptr<GroupSnapshot> group_snapshot_;                        // publisher thread (8 device snapshots)
  std::vector<std::unique_ptr<hapticd_msg_GroupState>> group_messages_;  // per group, the last (about 7 kB)
  std::vector<std::int64_t> group_written_ns_;                           // ... and when it was written
  std::mutex description_mutex_;
};

}  // namespace hapticd::server
