#include "support/temp_file.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "support/test_paths.hpp"

namespace hapticd::test {

std::filesystem::path write_temp_file(const std::string& name, const std::string& text) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "hapticd_tests" /
                              (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

std::string test_session_yaml(const std::string& server_yaml, const std::string& device_yaml) {
  return "server:\n  plugin_paths: [" + hapticd::test::plugin_dir() + "]\n" + server_yaml + "devices:\n" + device_yaml;
}

}  // namespace hapticd::test
