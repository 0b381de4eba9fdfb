#include "hapticd/recording/recording_export.hpp"

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "hapticd/recording/recording_reader.hpp"
#include "hdf5_support.hpp"

namespace hapticd::recording {
namespace {

using hdf5::check;
using hdf5::fail;
using hdf5::Handle;

std::vector<std::string> value_names(const std::string& path, int width, const std::vector<std::string>& joints) {
  std::string base = path;
  std::replace(base.begin(), base.end(), '/', '.');
  const bool joint_values = path.rfind("joints/", 0) == 0;
  if (width == 1 && !joint_values) return {base};
  static const char* const pose[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
  static const char* const spatial[] = {"x", "y", "z", "rx", "ry", "rz"};
  std::vector<std::string> out;
  for (int k = 0; k < width; ++k) {
    std::string suffix;
    if (joint_values && k < static_cast<int>(joints.size())) {
      suffix = joints[static_cast<std::size_t>(k)];
    } else if (width == 7) {
      suffix = pose[k];
    } else if (width == 6) {
      suffix = spatial[k];
    } else {
      suffix = std::to_string(k);
    }
    out.push_back(base + "." + suffix);
  }
  return out;
}

struct Column {
  Handle dataset;
  int width = 1;
  int rank = 1;
  bool integer = false;
  std::vector<double> reals;
  std::vector<std::int64_t> integers;
};

bool excluded(const std::string& path, const std::vector<std::string>& exclude) {
  return std::any_of(exclude.begin(), exclude.end(), [&](const std::string& e) {
    return path == e || (path.size() > e.size() && path.rfind(e, 0) == 0 && path[e.size()] == '/');
  });
}

constexpr hsize_t kBlockRows = 16384;

}  // namespace

std::size_t export_csv(const std::filesystem::path& file, const std::string& device, std::ostream& out,
                       const std::vector<std::string>& exclude) {
  const std::vector<std::string> devices = recorded_devices(file);
  if (std::find(devices.begin(), devices.end(), device) == devices.end())
    throw std::runtime_error(file.string() + " has no device '" + device + "'");
  const Handle f = hdf5::open_recording(file.string());
  const std::string group_path = "/devices/" + device;
  const Handle g(check(H5Gopen2(f.get(), group_path.c_str(), H5P_DEFAULT), "cannot open " + group_path));
  const std::vector<std::string> joints = hdf5::read_strings_attribute(g.get(), "joint_names");
  std::vector<Column> columns;
  std::string header;
  hsize_t rows = 0;
  bool first = true;
  for (const std::string& path : hdf5::read_strings_attribute(g.get(), "columns")) {
    if (excluded(path, exclude)) continue;
    Column c{Handle(check(H5Dopen2(g.get(), path.c_str(), H5P_DEFAULT), "cannot open " + group_path + "/" + path)),
             1,
             1,
             false,
             {},
             {}};
    const Handle space(check(H5Dget_space(c.dataset.get()), "H5Dget_space"));
    const Handle type(check(H5Dget_type(c.dataset.get()), "H5Dget_type"));
    hsize_t dims[2] = {0, 1};
    const int rank = H5Sget_simple_extent_dims(space.get(), dims, nullptr);
    if (rank < 1 || rank > 2) throw std::runtime_error(group_path + "/" + path + ": not a table");
    c.width = rank == 2 ? static_cast<int>(dims[1]) : 1;
    c.rank = rank;
    c.integer = H5Tget_class(type.get()) == H5T_INTEGER;
    if (first) {
      rows = dims[0];
    } else if (dims[0] != rows) {
      throw std::runtime_error(group_path + "/" + path + " has " + std::to_string(dims[0]) + " rows, the others " +
                               std::to_string(rows) + ": not a whole recording");
    }
    first = false;
    for (const std::string& name : value_names(path, c.width, joints)) header += (header.empty() ? "" : ",") + name;
    columns.push_back(std::move(c));
  }
  out << header << '\n';
  char text[40];
  std::string line;
  for (hsize_t start = 0; start < rows; start += kBlockRows) {
    const hsize_t n = std::min(kBlockRows, rows - start);
    for (Column& c : columns) {
      const hsize_t offset[2] = {start, 0};
      const hsize_t count[2] = {n, static_cast<hsize_t>(c.width)};
      const Handle file_space(check(H5Dget_space(c.dataset.get()), "H5Dget_space"));
      if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, offset, nullptr, count, nullptr) < 0)
        fail("H5Sselect_hyperslab");
      const Handle memory(check(H5Screate_simple(c.rank, count, nullptr), "H5Screate_simple"));
      const std::size_t values = static_cast<std::size_t>(n) * static_cast<std::size_t>(c.width);
      herr_t rc = 0;
      if (c.integer) {
        c.integers.resize(values);
        rc = H5Dread(c.dataset.get(), H5T_NATIVE_INT64, memory.get(), file_space.get(), H5P_DEFAULT, c.integers.data());
      } else {
        c.reals.resize(values);
        rc = H5Dread(c.dataset.get(), H5T_NATIVE_DOUBLE, memory.get(), file_space.get(), H5P_DEFAULT, c.reals.data());
      }
      if (rc < 0) fail("cannot read " + group_path);
    }
    for (hsize_t r = 0; r < n; ++r) {
      line.clear();
      for (const Column& c : columns) {
        for (int k = 0; k < c.width; ++k) {
          const std::size_t at =
              static_cast<std::size_t>(r) * static_cast<std::size_t>(c.width) + static_cast<std::size_t>(k);
          const int len = c.integer ? std::snprintf(text, sizeof text, "%" PRId64, c.integers[at])
                                    : std::snprintf(text, sizeof text, "%.17g", c.reals[at]);
          if (!line.empty()) line += ',';
          line.append(text, static_cast<std::size_t>(std::clamp(len, 0, static_cast<int>(sizeof text) - 1)));
        }
      }
      line += '\n';
      out << line;
    }
  }
  if (!out) throw std::runtime_error("cannot write the CSV");
  return static_cast<std::size_t>(rows);
}

}  // namespace hapticd::recording
