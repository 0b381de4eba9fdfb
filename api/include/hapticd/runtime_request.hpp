#pragma once
// Requests a plugin accepts while it runs, the same for every plugin kind (each interface derives from
// RuntimeRequests). Two routes, neither real-time (a server thread, never the loop, possibly while update() runs;
// the plugin hands what it accepted to its loop side lock-free, realtime::LatestValue, and applies it at a cycle
// boundary):
// - tune(parameters): a parameter the schema declares tunable was set; the server checked it against the schema,
//   keeps the values in effect (get requests read them there) and hands the plugin all of them.
// - handle_request(name, values): the plugin's own commands, names its schema does not declare (the simulated
//   operator's push and release). The default refuses.
// A client addresses them as "<stage>.<name>" on a device: device, virtual_model, inverse_kinematics, controller,
// or group_model (the model of the device's group) - docs/plugin-guide.md.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"

namespace hapticd {

struct RuntimeReply {
  RuntimeReply() = default;
  RuntimeReply(bool accepted_, std::string message_, std::vector<double> values_ = {})
      : accepted(accepted_), message(std::move(message_)), values(std::move(values_)) {}

  bool accepted = false;
  std::string message;         // why not, or what was done
  std::vector<double> values;  // a get request's answer: the value in effect (a boolean as 0 or 1)
};

// The run-time requests of a plugin: one piece every plugin interface shares.
class HAPTICD_API RuntimeRequests {
 public:
  virtual ~RuntimeRequests();

  // Not real-time safe, any server thread: a tunable parameter was set. `parameters` holds the value in effect of
  // every parameter, the new one checked against the schema. Read the tunable ones as configure() does and hand
  // them to the loop; throw ParameterError to refuse (the old values stay). The default refuses: a plugin that
  // declares tunable parameters overrides it.
  virtual void tune(const Parameters& parameters);
  // Not real-time safe, any server thread: a command of the plugin's own (a name the schema does not declare);
  // `values` its numbers. The default refuses.
  virtual RuntimeReply handle_request(std::string_view name, const std::vector<double>& values);
};

}  // namespace hapticd
