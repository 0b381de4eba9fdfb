#pragma once
// The web pages the engine socket serves from its own origin (which the Origin check admits), compiled in from
// tools/engine_socket/: a wall engine at http://ADDRESS:PORT/wall.html (wall.html) and the haptic scene drawn in
// 3-D, with a block the page pushes about by its own physics, at /scene.html (scene.html).
#include <string_view>

namespace hapticd::server {

[[nodiscard]] std::string_view wall_page() noexcept;
[[nodiscard]] std::string_view scene_page() noexcept;

}  // namespace hapticd::server
