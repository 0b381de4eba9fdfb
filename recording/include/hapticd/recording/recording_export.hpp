#pragma once
// CSV export of a hapticd recording (HDF5, docs/recording.md): one CSV per device, one row per cycle, the
// per-cycle datasets in the schema's order expanded to a column per value (joints by name, poses x y z qw qx qy
// qz, twists and wrenches x y z rx ry rz). Integers as integers, reals with 17 significant digits (identical
// files mean identical values). Reads in blocks: any length of recording.
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "hapticd/recording/recording_reader.hpp"

namespace hapticd::recording {

// Writes device's cycles as CSV. exclude: column paths (or their first segments, e.g. "timing") left out.
// Returns the rows written. Throws std::runtime_error.
std::size_t export_csv(const std::filesystem::path& file, const std::string& device, std::ostream& out,
                       const std::vector<std::string>& exclude = {});

}  // namespace hapticd::recording
