#include "support/test_paths.hpp"

namespace hapticd::test {

const std::string& source_dir() {
  static const std::string dir = HAPTICD_SOURCE_DIR;
  return dir;
}
const std::string& plugin_dir() {
  static const std::string dir = HAPTICD_TEST_PLUGIN_DIR;
  return dir;
}
const std::string& fixture_dir() {
  static const std::string dir = HAPTICD_TEST_FIXTURE_DIR;
  return dir;
}
const std::string& standin_dir() {
  static const std::string dir = HAPTICD_TEST_STANDIN_DIR;
  return dir;
}
const std::string& bin_dir() {
  static const std::string dir = HAPTICD_BIN_DIR;
  return dir;
}

}  // namespace hapticd::test
