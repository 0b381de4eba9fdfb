#pragma once
// A run-time request to one device: every request the DDS interface offers a client, as a value. The DDS
// interface and the in-process session (hapticd/server/session.hpp) route them through the same function.
#include <cstdint>
#include <string>
#include <vector>

namespace hapticd::server {

struct DeviceRequest {
  enum class Kind : std::uint8_t {
    switch_scheme,       // name: the scheme
    set_parameter,       // name: "<stage>.<parameter>" - stage device, virtual_model, inverse_kinematics,
                         // controller (the running scheme's), group_model (the device's group's), or safety
                         // (passivity_control); values: the new value of a parameter the
                         // plugin's schema declares tunable, checked against it; a name the schema does not
                         // declare is a command of the plugin's own
    get_parameter,       // name: "<stage>.<parameter>", any parameter of the schema; the reply's values (and
                         // message) carry the value in effect
    describe_parameter,  // name: "<stage>.<parameter>", or empty with values {K}: the K-th parameter of the
                         // device (its plugins' schemas in stage order, then the safety stage's); the reply
                         // describes it and its value in effect (hapticd/parameter_info.hpp)
    drive_operator,      // name: the simulated operator's request (push, release, ...), handled by the device plugin
    emergency_stop,      // the device goes to its safe state at the next cycle
    recover,             // leave the safe mode once it has settled
  };
  Kind kind = Kind::switch_scheme;
  std::string name;
  std::vector<double> values;
};

}  // namespace hapticd::server
