#pragma once
#include <atomic>

namespace hapticd::server {

// SIGINT and SIGTERM set this flag (async-signal-safe: a lock-free atomic store); the loop sees it at the next
// cycle and ramps the torques down. SIGXFSZ is ignored (a write past the file size limit fails and is reported).
const std::atomic<bool>& install_stop_signal_handlers();
// The same flag, for the process's own reasons to stop (a broken invariant off the loop: app/invariant_stop).
std::atomic<bool>& stop_flag();

}  // namespace hapticd::server
