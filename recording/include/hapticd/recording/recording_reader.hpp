#pragma once
// Reading a hapticd recording (HDF5, docs/recording.md) back into memory: a device's description as recorded
// and any of its per-cycle datasets as tables of doubles. For programs and plugins that replay or analyse a
// recording (the playback device); hapticctl export streams instead (recording_export.hpp).
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "hapticd/device_description.hpp"

namespace hapticd::recording {

// One dataset: `rows` cycles of `width` values, row after row.
struct Table {
  std::size_t rows = 0;
  std::size_t width = 0;
  std::vector<double> values;
  [[nodiscard]] const double* row(std::size_t r) const noexcept { return values.data() + r * width; }
};

struct RecordedDevice {
  std::string name;
  double rate_hz = 0.0;                   // the recording session's loop rate
  DeviceDescription description;          // as the recording describes the device (model, joints, frames,
                                          // robot model file, simulated, base pose)
  std::size_t cycles = 0;                 // rows of every dataset
  std::map<std::string, Table> datasets;  // the datasets asked for, by path ("joints/position")
};

// The devices of a recording, in its order. Throws std::runtime_error (not a hapticd recording, unreadable).
std::vector<std::string> recorded_devices(const std::filesystem::path& file);

// A device's description and the named datasets (any of the schema's; integers become doubles). Throws
// std::runtime_error naming the file and what is wrong (no such device or dataset, datasets of different
// lengths).
RecordedDevice read_device(const std::filesystem::path& file, const std::string& device,
                           const std::vector<std::string>& datasets);

}  // namespace hapticd::recording
