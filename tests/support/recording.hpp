#pragma once
// Reading a recording back in tests: each device's cycles as the CSV `hapticctl export` writes (timing left
// out unless asked: it is the machine's, not the run's).
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace hapticd::test {

// device -> CSV text (header and one row per cycle).
std::map<std::string, std::string> recording_csv(const std::filesystem::path& file,
                                                 const std::vector<std::string>& exclude = {"timing"});
// One device's column `name` (the CSV header's name, e.g. "joints.velocity.joint1"; a name ending in '.' takes
// the first column it begins) as numbers.
std::vector<double> recording_column(const std::string& csv, const std::string& name);

}  // namespace hapticd::test
