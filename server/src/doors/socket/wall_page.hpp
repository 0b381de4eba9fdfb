#pragma once
// A wall engine in a web page (tools/engine_socket/wall.html), served by the engine socket at
// http://ADDRESS:PORT/wall.html: a page from the socket's own origin, which the Origin check admits.
#include <string_view>

namespace hapticd::server {

[[nodiscard]] std::string_view wall_page() noexcept;

}  // namespace hapticd::server
