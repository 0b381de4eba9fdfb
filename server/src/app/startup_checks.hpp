#pragma once
// Checks made before any device is powered, for what would otherwise fail later or abort in a library: a
// process with too little address space left (ulimit -v) cannot create the threads of the DDS interface, and
// Cyclone DDS 0.10 aborts the process when its receive thread cannot be created.
#include <string>

namespace hapticd::server {

// Empty when the process can still map `threads` thread stacks (at the stack size limit, 8 MB by default)
// plus `extra_bytes`; otherwise a message that says what is missing and what to do.
std::string check_address_space(int threads, std::size_t extra_bytes);

}  // namespace hapticd::server
