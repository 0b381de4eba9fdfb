#pragma once
// What the example engines do when the server ends their claim (the engine seemed gone for longer than the
// server's claim hold: frozen, or its process stalled; docs/safety.md, "Ownership"): say so and claim again; if
// another engine took the device meanwhile, stop with a message (exit code 3).
#include <fmt/format.h>

#include <string_view>

#include "hapticd/client/client.hpp"

namespace hapticd::examples {

inline constexpr int kExitClaimLost = 3;

// Called now and then from the engine's main loop; false: the claim is lost for good.
inline bool keep_claim(client::Client& c, std::string_view device, std::string_view engine, bool group = false,
                       std::string_view any_device = {}) {
  if (!c.claim_lost(any_device.empty() ? device : any_device)) return true;
  fmt::print(stderr,
             "{}: the server ended the claim of '{}' (this engine seemed gone longer than its claim hold); "
             "claiming it again\n",
             engine, device);
  const client::Reply r = group ? c.claim_group(device) : c.claim(device);
  if (r.accepted) {
    fmt::print("{}: claimed '{}' again\n", engine, device);
    return true;
  }
  fmt::print(stderr, "{}: cannot claim '{}' again: {}\n", engine, device, r.message);
  return false;
}

}  // namespace hapticd::examples
