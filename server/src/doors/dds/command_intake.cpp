#include "doors/dds/command_intake.hpp"

#include <algorithm>
#include <string>

#include "executor/loop_clock.hpp"
#include "hapticd/dds/conversion.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {

CommandIntake::CommandIntake(DdsEndpoints& dds, Gate& gate)
    : dds_(dds),
      gate_(gate),
      instances_(std::make_unique<std::atomic<dds_instance_handle_t>[]>(gate.devices().size())),
      deadline_misses_(std::make_unique<std::atomic<std::uint64_t>[]>(gate.devices().size())) {}

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
  const dds::Listener request_listener(dds_create_listener(this));
  dds_lset_data_available(request_listener.get(),
                          [](dds_entity_t, void* self) { static_cast<CommandIntake*>(self)->gate_.wake(); });
  dds_.request.set_listener(request_listener.get());
}

void CommandIntake::close() {
  (void)dds_set_listener(dds_.command.get(), nullptr);  // no listener callback into the parts below
  (void)dds_set_listener(dds_.group_command.get(), nullptr);
  (void)dds_set_listener(dds_.request.get(), nullptr);
}

void CommandIntake::count_deadline_misses() {
  dds_requested_deadline_missed_status_t missed{};
  if (dds_get_requested_deadline_missed_status(dds_.command.get(), &missed) != DDS_RETCODE_OK ||
      missed.total_count_change <= 0)
    return;
  for (std::size_t i = 0; i < gate_.devices().size(); ++i)
    if (instances_[i].load(std::memory_order_relaxed) == missed.last_instance_handle)
      deadline_misses_[i].fetch_add(static_cast<std::uint64_t>(missed.total_count_change));
}

void CommandIntake::liveliness_changed(const dds_liveliness_changed_status_t& status) {
  dds_.peers.liveliness_changed(status);
  gate_.wake();  // the service thread checks the claims now
}

void CommandIntake::take_commands() {
  const std::lock_guard one_at_a_time(take_mutex_);
  dds_.command.take([&](const hapticd_msg_EngineCommand& c, const dds_sample_info_t& info) {
    DeviceGate* d = gate_.devices().find(dds::text_of(c.device));
    if (d == nullptr) return;  // (the reader's filter keeps other devices' commands out, and counts them)
    instances_[d->index].store(info.instance_handle, std::memory_order_relaxed);
    (void)gate_.admit(*d, c, sender_of(dds_.command.get(), info), info.source_timestamp);
  });
}

void CommandIntake::take_group_commands() {
  const std::lock_guard one_at_a_time(take_mutex_);
  dds_.group_command.take([&](const hapticd_msg_GroupCommand& g, const dds_sample_info_t& info) {
    DeviceGates& devices = gate_.devices();
    GroupGate* group = devices.find_group(dds::text_of(g.group));
    if (group == nullptr) return;  // (the reader's filter keeps other groups' commands out, and counts them)
    const Sender sender = sender_of(dds_.group_command.get(), info);
    const std::size_t count = std::min<std::size_t>(static_cast<std::size_t>(std::max(0, g.command_count)),
                                                    std::min<std::size_t>(group->members.size(), 8));
    if (count != group->members.size()) devices.count_unknown_command();  // a device of the group left out
    for (std::size_t k = 0; k < count; ++k) {
      DeviceGate& d = devices[group->members[k]];
      // Each in the group's order, for the device it names: otherwise malformed, never applied.
      if (dds::text_of(g.commands[k].device) != d.device->name()) {
        devices.count_unknown_command();
        continue;
      }
      (void)gate_.admit(d, g.commands[k], sender, info.source_timestamp);
    }
  });
}

Sender CommandIntake::sender_of(dds_entity_t reader, const dds_sample_info_t& info) {
  // Who wrote it (a writer no longer matched has no participant: it is nobody's command).
  return Sender{dds_.peers.participant_of(reader, info.publication_handle).value_or(PeerId{}), info.publication_handle};
}

}  // namespace hapticd::server
