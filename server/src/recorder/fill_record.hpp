#pragma once
// A device's cycle as the recording keeps it (hapticd/recording/cycle_record.hpp), from its session.
#include <cstdint>

#include "hapticd/cycle_time.hpp"
#include "hapticd/recording/cycle_record.hpp"

namespace hapticd::server {

class DeviceSession;

// The record of device `index` after limit_and_write() of this cycle (reads the session's own cycle snapshot,
// which the recorder makes it fill every cycle). Real-time safe.
void fill_cycle_record(recording::CycleRecord& r, const DeviceSession& session, std::uint16_t index,
                       const CycleTime& cycle, std::int64_t lateness_ns, std::int64_t compute_ns) noexcept;

}  // namespace hapticd::server
