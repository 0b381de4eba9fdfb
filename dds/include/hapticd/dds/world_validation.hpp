#pragma once
// Checks of an engine's world (hapticd_world) before the live view draws it: well-formed names, a shape count in
// range, known shapes, finite numbers within bounds. A world that fails is dropped and counted, never drawn.
// A pure function, fuzzed with the engine commands' checks.
#include <string_view>

#include "hapticd_msg.h"

namespace hapticd::dds {

struct WorldBounds {
  double max_size_m = 100.0;       // a shape's half-extent or radius
  double max_distance_m = 1000.0;  // a shape's position from the world's origin
};

// Empty when the world may be drawn, else why not (a static text).
[[nodiscard]] std::string_view check_world(const hapticd_msg_World& world, const WorldBounds& bounds = {}) noexcept;

}  // namespace hapticd::dds
