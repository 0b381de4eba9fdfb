#include "hapticd/recording/recording_reader.hpp"

#include <algorithm>
#include <stdexcept>

#include "hdf5_support.hpp"

namespace hapticd::recording {
namespace {

using hdf5::check;
using hdf5::fail;
using hdf5::Handle;

// What one dataset may make the reader allocate: its declared size at most this many times what the file
// stores for it (hapticd writes uncompressed: 1; a repacked, compressed copy stays well within), plus a chunk.
constexpr double kMaxExpansion = 64.0;
constexpr std::size_t kMaxValues = std::size_t{1} << 27;  // 1 GiB of doubles, whatever the file stores

Table read_table(hid_t group, const std::string& where, const std::string& path) {
  const std::string name = where + "/" + path;
  if (H5Lexists(group, path.c_str(), H5P_DEFAULT) <= 0) throw std::runtime_error("no dataset " + name);
  const Handle d(check(H5Dopen2(group, path.c_str(), H5P_DEFAULT), "no dataset " + name));
  const Handle type(check(H5Dget_type(d.get()), "H5Dget_type"));
  const H5T_class_t type_class = H5Tget_class(type.get());
  if (type_class != H5T_FLOAT && type_class != H5T_INTEGER)
    throw std::runtime_error(name + ": not numbers (the recording's datasets hold numbers)");
  const Handle space(check(H5Dget_space(d.get()), "H5Dget_space"));
  const int declared_rank = H5Sget_simple_extent_ndims(space.get());
  if (declared_rank < 1 || declared_rank > 2) throw std::runtime_error(name + ": not a table (rank 1 or 2)");
  hsize_t dims[2] = {0, 1};
  const int rank = H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  if (rank < 1 || rank > 2) throw std::runtime_error(name + ": not a table");
  Table t;
  t.rows = static_cast<std::size_t>(dims[0]);
  t.width = rank == 2 ? static_cast<std::size_t>(dims[1]) : 1;
  // Checked before anything is allocated: a small file must not make the reader take gigabytes.
  const double values = static_cast<double>(dims[0]) * static_cast<double>(rank == 2 ? dims[1] : 1);
  const double stored = static_cast<double>(H5Dget_storage_size(d.get()));
  const double element = static_cast<double>(std::max<std::size_t>(1, H5Tget_size(type.get())));
  if (values > static_cast<double>(kMaxValues) || values * element > kMaxExpansion * stored + (1 << 20))
    throw std::runtime_error(name + " declares " + std::to_string(t.rows) + " x " + std::to_string(t.width) +
                             " values but the file stores " + std::to_string(static_cast<long long>(stored)) +
                             " bytes of it: not read");
  t.values.resize(t.rows * t.width);
  if (!t.values.empty() && H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.values.data()) < 0)
    fail("cannot read " + where + "/" + path);
  return t;
}

std::vector<double> sized(std::vector<double> v, std::size_t n, const std::string& what) {
  if (v.size() != n)
    throw std::runtime_error(what + " has " + std::to_string(v.size()) + " values, not " + std::to_string(n));
  return v;
}

}  // namespace

std::vector<std::string> recorded_devices(const std::filesystem::path& file) {
  const Handle f = hdf5::open_recording(file.string());
  return hdf5::read_strings_attribute(f.get(), "devices");
}

RecordedDevice read_device(const std::filesystem::path& file, const std::string& device,
                           const std::vector<std::string>& datasets) {
  const Handle f = hdf5::open_recording(file.string());
  const std::vector<std::string> devices = hdf5::read_strings_attribute(f.get(), "devices");
  if (std::find(devices.begin(), devices.end(), device) == devices.end()) {
    std::string names;
    for (const std::string& d : devices) names += (names.empty() ? "" : ", ") + d;
    throw std::runtime_error(file.string() + " has no device '" + device + "' (it has " + names + ")");
  }
  RecordedDevice r;
  r.name = device;
  r.rate_hz = sized(hdf5::read_numbers_attribute(f.get(), "rate_hz"), 1, file.string() + " attribute rate_hz")[0];
  const std::string where = file.string() + ":/devices/" + device;
  const Handle g(check(H5Gopen2(f.get(), ("/devices/" + device).c_str(), H5P_DEFAULT), "cannot open " + where));
  DeviceDescription& d = r.description;
  d.model = hdf5::read_string_attribute(g.get(), "model");
  const std::vector<std::string> names = hdf5::read_strings_attribute(g.get(), "joint_names");
  const std::size_t n = names.size();
  const auto per_joint = [&](const char* attribute) {
    return sized(hdf5::read_numbers_attribute(g.get(), attribute), n, where + " attribute " + attribute);
  };
  const std::vector<double> qmin = per_joint("position_min"), qmax = per_joint("position_max"),
                            vmax = per_joint("velocity_max"), peak = per_joint("torque_peak"),
                            continuous = per_joint("torque_continuous");
  for (std::size_t j = 0; j < n; ++j) d.joints.push_back({names[j], qmin[j], qmax[j], vmax[j], peak[j], continuous[j]});
  d.handle_frame = hdf5::read_string_attribute(g.get(), "handle_frame");
  d.sensor_frame = hdf5::read_string_attribute(g.get(), "sensor_frame");
  d.robot_model_file = hdf5::read_string_attribute(g.get(), "robot_model_file");
  d.simulated = sized(hdf5::read_numbers_attribute(g.get(), "simulated"), 1, where + " attribute simulated")[0] != 0.0;
  const std::vector<double> base = sized(hdf5::read_numbers_attribute(g.get(), "base_pose"), 7, where + " base_pose");
  d.base_pose.position = Eigen::Vector3d(base[0], base[1], base[2]);
  d.base_pose.orientation = Eigen::Quaterniond(base[3], base[4], base[5], base[6]).normalized();
  bool first = true;
  for (const std::string& path : datasets) {
    Table t = read_table(g.get(), where, path);
    if (!first && t.rows != r.cycles)
      throw std::runtime_error(where + "/" + path + " has " + std::to_string(t.rows) + " rows, the others " +
                               std::to_string(r.cycles) + ": not a whole recording");
    r.cycles = t.rows;
    first = false;
    r.datasets.emplace(path, std::move(t));
  }
  return r;
}

}  // namespace hapticd::recording
