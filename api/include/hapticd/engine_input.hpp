#pragma once
// What an external rendering engine last sent for a device (the DDS interface writes it; the server hands
// the newest one to the virtual model each cycle). An impedance-type engine sends a proxy pose (the "god
// object" its virtual world allows) that the virtual coupling ties the device to; an engine may instead send
// a wrench to display directly. Fixed-size: copying it never allocates.
#include <cstdint>

#include "hapticd/spatial.hpp"

namespace hapticd {

struct EngineInput {
  Pose proxy_pose;
  Twist proxy_twist;
  bool has_proxy = false;
  Wrench wrench;                 // world, at the handle: what the engine's world applies to the handle
  bool has_wrench = false;
  std::int64_t received_ns = 0;  // loop time at which the server received it
  std::uint64_t sequence = 0;    // increments with every message from the engine
};

}  // namespace hapticd
