#pragma once
// The friction parameter file: what the friction identification writes (hapticd-eval identify-friction) and
// the compensators load (the impedance controller's `friction_file`). YAML, one entry per joint:
//   device: vishard3
//   joints:
//     - {name: joint1, coulomb: 1.18, viscous: [p1, p2, p3, p4], load: [a0, a1, a2], velocity_max: 5.0,
//        breakaway: 1.35}
#include <filesystem>
#include <string>
#include <vector>

#include "hapticd/export.hpp"
#include "hapticd/model/friction_model.hpp"

namespace hapticd::model {

struct FrictionFile {
  std::string device;
  std::vector<std::string> joint_names;
  std::vector<FrictionModel> joints;
};

// Throws ModelError naming the file, line and key of the first problem.
[[nodiscard]] HAPTICD_API FrictionFile read_friction_file(const std::filesystem::path& file);
// Throws ModelError when the file cannot be written.
HAPTICD_API void write_friction_file(const std::filesystem::path& file, const FrictionFile& friction);

}  // namespace hapticd::model
