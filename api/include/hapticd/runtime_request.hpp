#pragma once
// Requests a plugin accepts while it runs (from the DDS interface: set a parameter, drive a simulated
// operator). Not real-time: handle_request() is called on a server thread, never the loop, possibly while
// update() runs; a plugin hands what it accepted to its loop side lock-free (realtime::LatestValue) and
// applies it at a cycle boundary. The default refuses everything.
#include <string>
#include <string_view>
#include <vector>

namespace hapticd {

struct RuntimeReply {
  bool accepted = false;
  std::string message;  // why not, or what was done
};

}  // namespace hapticd
