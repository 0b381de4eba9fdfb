#pragma once
#include <filesystem>
#include <string>

namespace hapticd::test {

// Writes text to a fresh file in the test's temporary folder and returns its path.
std::filesystem::path write_temp_file(const std::string& name, const std::string& text);

// A session file for the test plugins. extra_device_yaml is inserted into the device entry.
std::string test_session_yaml(const std::string& server_yaml, const std::string& device_yaml);

}  // namespace hapticd::test
