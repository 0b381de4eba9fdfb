#include "gate/event_fanout.hpp"

#include "hapticd/dds/conversion.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {

void EventFanout::send(const DeviceGate& device, hapticd_msg_EventKind kind, std::string_view code,
                       std::string_view message) {
  hapticd_msg_Event e{};
  dds::set_text(e.device, device.device->name());
  e.serial = serial_.fetch_add(1) + 1;
  e.loop_time_ns = device.loop_time_ns.load(std::memory_order_relaxed);
  e.kind = kind;
  dds::set_text(e.code, code);
  dds::set_text(e.message, message);
  for (Door* door : doors_) door->event(e);
}

}  // namespace hapticd::server
