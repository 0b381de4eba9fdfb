#pragma once
// Sends a device's events (any of the bridge's threads): numbered across the session, stamped with the loop
// time of the device's newest published state.
#include <atomic>
#include <cstdint>
#include <string_view>

#include "bridge/device_link.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "hapticd_msg.h"

namespace hapticd::server {

class EventSender {
 public:
  explicit EventSender(const dds::Writer<hapticd_msg_Event>& writer) : writer_(writer) {}
  void send(const DeviceLink& device, hapticd_msg_EventKind kind, std::string_view code, std::string_view message);

 private:
  const dds::Writer<hapticd_msg_Event>& writer_;
  std::atomic<std::uint64_t> serial_{0};
};

}  // namespace hapticd::server
