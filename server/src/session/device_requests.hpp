#pragma once
// Every run-time request a client can make of one device, and the one place that carries it out. The DDS
// interface's request dispatcher and the in-process session API both route through apply_request, so a request
// means the same whichever way it comes. Not real-time, never the loop thread; ownership is the caller's check.
#include <cstdint>
#include <string>
#include <vector>

#include "hapticd/runtime_request.hpp"

namespace hapticd::server {

class DeviceSession;

struct DeviceRequest {
  enum class Kind : std::uint8_t {
    switch_scheme,   // name: the scheme
    set_parameter,   // name: "<stage>.<parameter>" - stage device, virtual_model, inverse_kinematics, controller,
                     // safety (passivity_control); values: the new value, checked against the plugin's schema
    drive_operator,  // name: the simulated operator's request (push, release, ...), handled by the device plugin
    emergency_stop,  // the device goes to its safe state at the next cycle
    recover,         // leave the safe mode once it has settled
  };
  Kind kind = Kind::switch_scheme;
  std::string name;
  std::vector<double> values;
};

RuntimeReply apply_request(DeviceSession& device, const DeviceRequest& request);

}  // namespace hapticd::server
