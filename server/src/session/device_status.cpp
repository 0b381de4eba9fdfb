#include "session/device_status.hpp"

namespace hapticd::server {

std::string DeviceStatus::fault_text() const {
  const DeviceFault f = fault();
  if (f == DeviceFault::none) return {};
  std::string text(to_string(f));
  if (const char* reason = fault_reason()) text += std::string(": ") + reason;
  return text;
}

}  // namespace hapticd::server
