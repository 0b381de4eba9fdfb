#pragma once
// Where the tests find the repository, the built plugins and the loader's fixtures. Absolute paths, compiled into
// one file (test_paths.cpp): every other test file is then the same text in every clone, and a compiler cache
// shared between clones (CI's, a second checkout) serves it instead of compiling it again.
#include <string>

namespace hapticd::test {

const std::string& source_dir();   // the repository
const std::string& plugin_dir();   // the plugins of this build
const std::string& fixture_dir();  // libraries that are deliberately not valid plugins
const std::string& standin_dir();  // the vendors' SDK stand-ins, one folder per vendor (tests/standins)
const std::string& bin_dir();      // the programs of this build (hapticctl, the engines)

}  // namespace hapticd::test
