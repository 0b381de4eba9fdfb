// libFuzzer target: the session-file loader (YAML parsing, the server/dds/devices schemas, the per-device
// safety section). Any bytes are written as a session file and loaded: the loader either returns a config or
// throws a ConfigError; any other exception escaping, or a crash, is the finding. Seeds: config/sessions.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "config/config_error.hpp"
#include "config/session_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("hapticd-fuzz-session-" + std::to_string(::getpid()) + ".yaml");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    (void)hapticd::server::load_session_config(file);
  } catch (const hapticd::server::ConfigError&) {
    // the expected answer to a bad file
  }
  return 0;
}
