#pragma once
// What hapticd does with a broken invariant (HAPTICD_DEMAND) on a thread that is not a real-time loop - the DDS
// gate's and the doors' threads, the monitor, the recorder, the live view (docs/safety.md, "Invariants and input"): no
// abort, which would cut every drive's power without its safe ramp. The failing thread cannot go on (its invariant is
// broken), so it: records what failed, asks every device to stop through its safe mode (the flag the loops watch, as
// SIGTERM does), waits until the loops have brought their devices to rest, and ends the process with exit code 4. A
// loop thread still aborts: nothing else could take its devices to their safe mode.
#include <atomic>
#include <optional>
#include <string>

namespace hapticd::server {

// Installs the handler; `stop` is the flag the executor's loops watch (the signal handlers' flag).
void install_invariant_stop(std::atomic<bool>& stop);
// The invariant that failed on a non-loop thread, if one did ("condition (file:line)").
[[nodiscard]] std::optional<std::string> invariant_failure();

}  // namespace hapticd::server
