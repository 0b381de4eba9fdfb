#include "bridge/command_intake.hpp"

#include <string>

#include "executor/loop_clock.hpp"
#include "hapticd/dds/conversion.hpp"
#include "session/device_session.hpp"

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
}

void CommandIntake::liveliness_changed(const dds_liveliness_changed_status_t& status) {
  dds_.peers.liveliness_changed(status);
  (void)dds_set_guardcondition(dds_.wake.get(), true);  // the receiver checks the claims now
}

void CommandIntake::take_commands() {
  const std::lock_guard one_at_a_time(take_mutex_);
  dds_.command.take([&](const hapticd_msg_EngineCommand& c, const dds_sample_info_t& info) {
    const std::int64_t now_wall = dds::wall_clock_ns();
    DeviceLink* d = links_.find(dds::text_of(c.device));
    if (d == nullptr) return;  // (the reader's filter keeps other devices' commands out, and counts them)
    // Who wrote it (a writer no longer matched has no participant: it is nobody's command).
    const Sender sender{dds_.peers.participant_of(dds_.command.get(), info.publication_handle).value_or(PeerId{}),
                        info.publication_handle};
    d->instance.store(info.instance_handle, std::memory_order_relaxed);
    CommandGate::Verdict v;
    {
      std::lock_guard lock(d->mutex);
      v = d->gate.admit(c, sender, info.source_timestamp, now_wall);
    }
    if (!v.accepted) {
      if (d->reject_events[static_cast<std::size_t>(v.reason)]++ % 100 == 0)  // the first, then every 100th per reason
        events_.send(*d, hapticd_msg_EVENT_ENGINE_REJECTED, dds::to_string(v.reason),
                     "engine command rejected from '" + std::string(dds::text_of(c.engine)) +
                         "': " + std::string(dds::to_string(v.reason)));
      return;
    }
    const std::int64_t state_written_ns = d->round_trip.command_accepted(c.serial, c.state_serial);
    d->session->publish_engine_input(dds::to_engine_input(c));
    d->round_trip.command_handed_over(state_written_ns, monotonic_now_ns());
    if (c.state_serial > 0) {
      if (c.state_serial > d->answered.load(std::memory_order_relaxed))
        d->answered.store(c.state_serial, std::memory_order_release);
      d->synced.store(true, std::memory_order_release);
    }
  });
}

}  // namespace hapticd::server
