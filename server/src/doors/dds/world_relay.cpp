#include "doors/dds/world_relay.hpp"

#include <spdlog/spdlog.h>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/world_validation.hpp"

namespace hapticd::server {

WorldRelay::WorldRelay(const dds::Participant& participant, Sink sink) : sink_(std::move(sink)), reader_(participant) {
  const dds::Listener listener(dds_create_listener(this));
  dds_lset_data_available(listener.get(), [](dds_entity_t, void* self) { static_cast<WorldRelay*>(self)->take(); });
  reader_.set_listener(listener.get());
}

WorldRelay::~WorldRelay() { (void)dds_set_listener(reader_.get(), nullptr); }

void WorldRelay::take() {
  const std::lock_guard one_at_a_time(take_mutex_);
  reader_.take([&](const hapticd_msg_World& w, const dds_sample_info_t&) {
    const std::string_view why = dds::check_world(w);
    if (!why.empty()) {
      // Told once, then every 1000th: a viewer's picture is not worth a flood of log lines.
      if (rejected_.fetch_add(1, std::memory_order_relaxed) % 1000 == 0) {
        spdlog::warn("a world on hapticd_world was dropped: {} (engine '{}'; {} dropped so far)", why,
                     dds::terminated(w.engine) ? dds::text_of(w.engine) : std::string_view("?"), rejected());
      }
      return;
    }
    accepted_.fetch_add(1, std::memory_order_relaxed);
    sink_(w);
  });
}

}  // namespace hapticd::server
