#pragma once
// The live view's own page (tools/live_view/viewer.html), served at http://ADDRESS:PORT/ by the live view: a
// page from the server's own origin, which the Origin check admits.
#include <string_view>

namespace hapticd::server::live_view {

[[nodiscard]] std::string_view viewer_page() noexcept;

}  // namespace hapticd::server::live_view
