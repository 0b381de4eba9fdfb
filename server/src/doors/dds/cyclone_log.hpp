#pragma once
// Cyclone DDS's own log (warnings about malformed packets, discovery problems, ...) goes through the server's
// logger instead of straight to stderr, rate-limited: a flood of junk packets made Cyclone write one warning per
// packet (67 MB in 20 s) and slowed the receive path. At most `lines_per_s` lines (a burst of `burst`) pass; the
// rest are counted and summarised by report_suppressed() (docs/safety.md). Process-wide, as Cyclone's sink is;
// never on the loop (Cyclone's threads call it).
#include <cstdint>

namespace hapticd::server::cyclone_log {

// Installs the route (idempotent: a later call only changes the rate).
void route_to_logger(double lines_per_s, double burst);

struct Counts {
  std::uint64_t forwarded = 0;
  std::uint64_t suppressed = 0;
};
[[nodiscard]] Counts counts() noexcept;

// Logs one line with the number of lines suppressed since the last call, if any (the bridge calls it every few
// seconds and at the end).
void report_suppressed();

}  // namespace hapticd::server::cyclone_log
