#pragma once
#include <atomic>

namespace hapticd::server {

// SIGINT and SIGTERM set this flag (async-signal-safe: a lock-free atomic store); the loop sees it at the next
// cycle and ramps the torques down.
const std::atomic<bool>& install_stop_signal_handlers();

}  // namespace hapticd::server
