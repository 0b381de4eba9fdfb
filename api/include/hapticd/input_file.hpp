#pragma once
// Reading an input file (session file, robot model, friction file) safely: only a regular file (a directory,
// a named pipe or a device such as /dev/zero is refused before anything is read), no larger than a limit, read
// whole. Errors are std::runtime_error with a message that names the file and says what is wrong.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "hapticd/export.hpp"

namespace hapticd {

// Generous for every file hapticd reads (the shipped ones are below 100 kB).
inline constexpr std::size_t kMaxInputFileBytes = 4u * 1024u * 1024u;

// `what` names the kind of file in messages ("session file", "robot model").
HAPTICD_API std::string read_input_file(const std::filesystem::path& file, std::string_view what,
                                        std::size_t max_bytes = kMaxInputFileBytes);

}  // namespace hapticd
