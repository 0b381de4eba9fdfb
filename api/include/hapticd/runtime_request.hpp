#pragma once
// Requests a plugin accepts while it runs. Two routes, neither real-time (a server thread, never the loop,
// possibly while update() runs; the plugin hands what it accepted to its loop side lock-free,
// realtime::LatestValue, and applies it at a cycle boundary):
// - tune(parameters): a parameter the schema declares tunable was set; the server checked it against the schema,
//   keeps the values in effect (get requests read them there) and hands the plugin all of them.
// - handle_request(name, values): the plugin's own commands, names its schema does not declare (the simulated
//   operator's push and release). The default refuses.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hapticd {

struct RuntimeReply {
  RuntimeReply() = default;
  RuntimeReply(bool accepted_, std::string message_, std::vector<double> values_ = {})
      : accepted(accepted_), message(std::move(message_)), values(std::move(values_)) {}

  bool accepted = false;
  std::string message;         // why not, or what was done
  std::vector<double> values;  // a get request's answer: the value in effect (a boolean as 0 or 1)
};

}  // namespace hapticd
