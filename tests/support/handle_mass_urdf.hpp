#pragma once
// The ViSHaRD3 model with a handle of the given mass beyond its force sensor (what a gimbal would weigh), written
// to a temporary file: for the tests of what the sensor carries (the simulation's reading, the server's weight
// compensation). Returns the file's path.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "support/test_paths.hpp"

namespace hapticd::test {

inline std::string vishard3_urdf_with_handle_mass(double mass_kg) {
  std::ifstream in(hapticd::test::source_dir() + "/config/urdf/vishard3.urdf");
  std::stringstream text;
  text << in.rdbuf();
  std::string urdf = text.str();
  const std::string massless = "<link name=\"handle\"/>";
  const auto at = urdf.find(massless);
  if (at == std::string::npos) throw std::runtime_error("vishard3.urdf: no massless handle link");
  urdf.replace(
      at, massless.size(),
      "<link name=\"handle\"><inertial><origin xyz=\"0 0 0\"/><mass value=\"" + std::to_string(mass_kg) +
          "\"/><inertia ixx=\"1e-4\" iyy=\"1e-4\" izz=\"1e-4\" ixy=\"0\" iyz=\"0\" ixz=\"0\"/></inertial></link>");
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("hapticd_vishard3_handle_" + std::to_string(mass_kg) + ".urdf");
  std::ofstream(file) << urdf;
  return file.string();
}

}  // namespace hapticd::test
