#pragma once
// The bridge's command path, on Cyclone's receive threads (a listener: no thread wake-up between a command's
// arrival and its hand-over to the loop): who wrote it (PeerDirectory), whether its device accepts it
// (CommandGate: owner, order, freshness, content), the hand-over (DeviceRequests::engine_input,
// lock-free), the round-trip probe and the lockstep hand-shake. Rejections are counted by the gate and announced
// (the first, then every 100th per reason). Command writers' liveliness changes go to the PeerDirectory and
// wake the receiver, which checks the claims.
#include <array>
#include <mutex>
#include <vector>

#include "bridge/dds_endpoints.hpp"
#include "bridge/device_link.hpp"
#include "bridge/event_sender.hpp"

namespace hapticd::server {

class CommandIntake {
 public:
  CommandIntake(DdsEndpoints& dds, DeviceLinks& links, EventSender& events);
  // Attaches the listener to the command reader; from then on commands flow. Last, once everything is built.
  void listen();
  // The engine socket's thread: a command from its client `connection`, received now, through the same gate as
  // a DDS writer's (the connection is the writer, its peer the participant). The gate's verdict.
  CommandGate::Verdict admit_from_socket(const hapticd_msg_EngineCommand& c, std::uint64_t connection);

 private:
  void take_commands();
  // A group's commands (one GroupCommand per cycle from the engine that claimed the group): each part as a
  // device's command.
  void take_group_commands();
  Sender sender_of(dds_entity_t reader, const dds_sample_info_t& info);
  // The gate's verdict on one device's command; an accepted one goes to the loop.
  CommandGate::Verdict admit(DeviceLink& d, const hapticd_msg_EngineCommand& c, const Sender& sender,
                             dds_time_t source_timestamp);
  void liveliness_changed(const dds_liveliness_changed_status_t& status);

  DdsEndpoints& dds_;
  DeviceLinks& links_;
  EventSender& events_;
  std::mutex take_mutex_;  // one take at a time: local writers deliver on their own threads, buffers are shared
};

}  // namespace hapticd::server
