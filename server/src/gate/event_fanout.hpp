#pragma once
// A device's events, from any of the gate's threads or a door's, to every door (Door::event): numbered across the
// session, stamped with the loop time of the device's newest published state.
#include <atomic>
#include <cstdint>
#include <string_view>
#include <vector>

#include "gate/device_gate.hpp"
#include "gate/door.hpp"
#include "hapticd_msg.h"

namespace hapticd::server {

class EventFanout {
 public:
  // Before any event: the doors (fixed from then on).
  void set_doors(std::vector<Door*> doors) { doors_ = std::move(doors); }
  void send(const DeviceGate& device, hapticd_msg_EventKind kind, std::string_view code, std::string_view message);

 private:
  std::vector<Door*> doors_;
  std::atomic<std::uint64_t> serial_{0};
};

}  // namespace hapticd::server
