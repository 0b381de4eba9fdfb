#include "bridge/command_intake.hpp"

#include <algorithm>
#include <string>

#include "executor/loop_clock.hpp"
#include "hapticd/dds/conversion.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {

CommandIntake::CommandIntake(DdsEndpoints& dds, DeviceLinks& links, EventSender& events)
    : dds_(dds), links_(links), events_(events) {}

void CommandIntake::listen() {
  const dds::Listener listener(dds_create_listener(this));
  dds_lset_data_available(listener.get(),
                          [](dds_entity_t, void* self) { static_cast<CommandIntake*>(self)->take_commands(); });
  dds_lset_liveliness_changed(listener.get(),
                              [](dds_entity_t, const dds_liveliness_changed_status_t status, void* self) {
                                static_cast<CommandIntake*>(self)->liveliness_changed(status);
                              });
  dds_.command.set_listener(listener.get());
  const dds::Listener group_listener(dds_create_listener(this));
  dds_lset_data_available(group_listener.get(),
                          [](dds_entity_t, void* self) { static_cast<CommandIntake*>(self)->take_group_commands(); });
  dds_lset_liveliness_changed(group_listener.get(),
                              [](dds_entity_t, const dds_liveliness_changed_status_t status, void* self) {
                                static_cast<CommandIntake*>(self)->liveliness_changed(status);
                              });
  dds_.group_command.set_listener(group_listener.get());
}

void CommandIntake::liveliness_changed(const dds_liveliness_changed_status_t& status) {
  dds_.peers.liveliness_changed(status);
  (void)dds_set_guardcondition(dds_.wake.get(), true);  // the receiver checks the claims now
}

void CommandIntake::take_commands() {
  const std::lock_guard one_at_a_time(take_mutex_);
  dds_.command.take([&](const hapticd_msg_EngineCommand& c, const dds_sample_info_t& info) {
    DeviceLink* d = links_.find(dds::text_of(c.device));
    if (d == nullptr) return;  // (the reader's filter keeps other devices' commands out, and counts them)
    d->instance.store(info.instance_handle, std::memory_order_relaxed);
    (void)admit(*d, c, sender_of(dds_.command.get(), info), info.source_timestamp);
  });
}

void CommandIntake::take_group_commands() {
  const std::lock_guard one_at_a_time(take_mutex_);
  dds_.group_command.take([&](const hapticd_msg_GroupCommand& g, const dds_sample_info_t& info) {
    GroupLink* group = links_.find_group(dds::text_of(g.group));
    if (group == nullptr) return;  // (the reader's filter keeps other groups' commands out, and counts them)
    const Sender sender = sender_of(dds_.group_command.get(), info);
    const std::size_t count = std::min<std::size_t>(static_cast<std::size_t>(std::max(0, g.command_count)),
                                                    std::min<std::size_t>(group->members.size(), 8));
    if (count != group->members.size()) links_.count_unknown_command();  // a device of the group left out
    for (std::size_t k = 0; k < count; ++k) {
      DeviceLink& d = links_[group->members[k]];
      // Each in the group's order, for the device it names: otherwise malformed, never applied.
      if (dds::text_of(g.commands[k].device) != d.device->name()) {
        links_.count_unknown_command();
        continue;
      }
      (void)admit(d, g.commands[k], sender, info.source_timestamp);
    }
  });
}

Sender CommandIntake::sender_of(dds_entity_t reader, const dds_sample_info_t& info) {
  // Who wrote it (a writer no longer matched has no participant: it is nobody's command).
  return Sender{dds_.peers.participant_of(reader, info.publication_handle).value_or(PeerId{}), info.publication_handle};
}

CommandGate::Verdict CommandIntake::admit_from_socket(const hapticd_msg_EngineCommand& c, std::uint64_t connection) {
  const std::lock_guard one_at_a_time(take_mutex_);
  DeviceLink* d = links_.find(dds::text_of(c.device));
  if (d == nullptr) {
    links_.count_unknown_command();
    return {false, dds::RejectReason::malformed};
  }
  return admit(*d, c, Sender{PeerId::of_socket(connection), socket_writer(connection)}, dds::wall_clock_ns());
}

CommandGate::Verdict CommandIntake::admit(DeviceLink& d, const hapticd_msg_EngineCommand& c, const Sender& sender,
                                          dds_time_t source_timestamp) {
  CommandGate::Verdict v;
  {
    std::lock_guard lock(d.mutex);
    v = d.gate.admit(c, sender, source_timestamp, dds::wall_clock_ns());
  }
  if (!v.accepted) {
    if (d.reject_events[static_cast<std::size_t>(v.reason)]++ % 100 == 0)  // the first, then every 100th per reason
      events_.send(d, hapticd_msg_EVENT_ENGINE_REJECTED, dds::to_string(v.reason),
                   "engine command rejected from '" + std::string(dds::text_of(c.engine)) +
                       "': " + std::string(dds::to_string(v.reason)));
    return v;
  }
  const std::int64_t state_written_ns = d.round_trip.command_accepted(c.serial, c.state_serial);
  d.device->engine_input(dds::to_engine_input(c));
  d.round_trip.command_handed_over(state_written_ns, monotonic_now_ns());
  if (c.state_serial > 0) {
    if (c.state_serial > d.answered.load(std::memory_order_relaxed))
      d.answered.store(c.state_serial, std::memory_order_release);
    d.synced.store(true, std::memory_order_release);
  }
  return v;
}

}  // namespace hapticd::server
