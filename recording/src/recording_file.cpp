#include "hapticd/recording/recording_file.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "hapticd/state_flags.hpp"
#include "hdf5_support.hpp"

namespace hapticd::recording {
namespace {

using hdf5::check;
using hdf5::fail;
using hdf5::Handle;
using hdf5::quiet;

// ---- the schema's per-cycle columns ------------------------------------------------------------------------
using Extract = void (*)(const CycleRecord&, unsigned char* out);

template <typename T>
void store(unsigned char* out, int k, T v) {
  std::memcpy(out + static_cast<std::size_t>(k) * sizeof(T), &v, sizeof(T));
}
template <std::size_t N>
void store_all(unsigned char* out, const double (&v)[N], int n) {
  std::memcpy(out, v, static_cast<std::size_t>(n) * sizeof(double));
}

struct Column {
  RecordingColumn meta;
  Extract extract;
};

#define HAPTICD_JOINTS(field) [](const CycleRecord& r, unsigned char* o) { store_all(o, r.field, r.dof); }
#define HAPTICD_ARRAY(field) \
  [](const CycleRecord& r, unsigned char* o) { store_all(o, r.field, static_cast<int>(std::size(r.field))); }
#define HAPTICD_SCALAR(field) [](const CycleRecord& r, unsigned char* o) { store(o, 0, r.field); }

const std::vector<Column>& columns() {
  static const std::vector<Column> c = {
      {{"cycle", "u64", 1, "", "the cycle's index (period number on the loop clock)"}, HAPTICD_SCALAR(cycle)},
      {{"time_s", "f64", 1, "s", "the cycle's time on the loop clock"},
       [](const CycleRecord& r, unsigned char* o) { store(o, 0, static_cast<double>(r.time_ns) * 1e-9); }},
      {{"joints/position", "f64", 0, "rad or m", "measured joint positions"}, HAPTICD_JOINTS(position)},
      {{"joints/velocity", "f64", 0, "rad/s or m/s", "the server's joint-velocity estimate (every plugin's)"},
       HAPTICD_JOINTS(velocity)},
      {{"joints/torque_command", "f64", 0, "N m or N", "torque written to the drives (after the safety supervisor)"},
       HAPTICD_JOINTS(torque_command)},
      {{"joints/torque_measured", "f64", 0, "N m or N",
        "the device's effort (joint torque sensors where it has them, else its drive torque)"},
       HAPTICD_JOINTS(torque_measured)},
      {{"handle/pose", "f64", 7, "m, quaternion", "handle pose, world: x y z qw qx qy qz"}, HAPTICD_ARRAY(handle_pose)},
      {{"handle/twist", "f64", 6, "m/s, rad/s", "handle twist, world: vx vy vz wx wy wz"}, HAPTICD_ARRAY(handle_twist)},
      {{"handle/buttons", "u32", 1, "", "the handle's buttons, bit i: button i pressed"}, HAPTICD_SCALAR(buttons)},
      {{"handle/gripper", "f64", 1, "rad", "the gripper's opening (0 without one)"}, HAPTICD_SCALAR(gripper)},
      {{"wrench/operator", "f64", 6, "N, N m", "the operator's wrench on the handle, world"},
       HAPTICD_ARRAY(operator_wrench)},
      {{"wrench/environment", "f64", 6, "N, N m", "the wrench the virtual model rendered, world"},
       HAPTICD_ARRAY(environment_wrench)},
      {{"wrench/sensor", "f64", 6, "N, N m", "the force/torque sensor's reading, sensor frame (zeros without one)"},
       HAPTICD_ARRAY(sensor_wrench)},
      {{"target/pose", "f64", 7, "m, quaternion", "the chain's desired pose, world: x y z qw qx qy qz"},
       HAPTICD_ARRAY(target_pose)},
      {{"mode", "u8", 1, "", "device mode, an index into the device's mode_names attribute"}, HAPTICD_SCALAR(mode)},
      {{"flags", "u32", 1, "", "state flags, bit i named by the device's flag_names attribute"}, HAPTICD_SCALAR(flags)},
      {{"scheme", "u16", 1, "", "the running control scheme, an index into the device's schemes attribute"},
       HAPTICD_SCALAR(scheme)},
      {{"engine/weight", "f64", 1, "", "the engine input's weight: 1 fresh, between 0 and 1 fading, 0 none"},
       HAPTICD_SCALAR(engine_weight)},
      {{"engine/sequence", "u64", 1, "", "serial number of the engine input in effect (0: none yet)"},
       HAPTICD_SCALAR(engine_sequence)},
      {{"engine/proxy_pose", "f64", 7, "m, quaternion", "the engine's proxy pose in effect (zeros: none sent)"},
       HAPTICD_ARRAY(engine_proxy_pose)},
      {{"engine/wrench", "f64", 6, "N, N m", "the engine's wrench in effect (zeros: none sent)"},
       HAPTICD_ARRAY(engine_wrench)},
      {{"timing/lateness_ns", "i64", 1, "ns", "how late the loop woke for this cycle (0 in lockstep)"},
       HAPTICD_SCALAR(lateness_ns)},
      {{"timing/compute_ns", "i64", 1, "ns", "from the cycle's start to this device's torque written"},
       HAPTICD_SCALAR(compute_ns)},
  };
  return c;
}

#undef HAPTICD_JOINTS
#undef HAPTICD_ARRAY
#undef HAPTICD_SCALAR

std::size_t type_size(const char* t) {
  if (std::strcmp(t, "u8") == 0) return 1;
  if (std::strcmp(t, "u16") == 0) return 2;
  if (std::strcmp(t, "u32") == 0) return 4;
  return 8;
}

hid_t memory_type(const char* t) {
  if (std::strcmp(t, "f64") == 0) return H5T_NATIVE_DOUBLE;
  if (std::strcmp(t, "i64") == 0) return H5T_NATIVE_INT64;
  if (std::strcmp(t, "u64") == 0) return H5T_NATIVE_UINT64;
  if (std::strcmp(t, "u32") == 0) return H5T_NATIVE_UINT32;
  if (std::strcmp(t, "u16") == 0) return H5T_NATIVE_UINT16;
  return H5T_NATIVE_UINT8;
}

hid_t file_type(const char* t) {
  if (std::strcmp(t, "f64") == 0) return H5T_IEEE_F64LE;
  if (std::strcmp(t, "i64") == 0) return H5T_STD_I64LE;
  if (std::strcmp(t, "u64") == 0) return H5T_STD_U64LE;
  if (std::strcmp(t, "u32") == 0) return H5T_STD_U32LE;
  if (std::strcmp(t, "u16") == 0) return H5T_STD_U16LE;
  return H5T_STD_U8LE;
}

// Bytes the file may still grow by: the free space of its file system (for an unprivileged user) and the
// process's file size limit (RLIMIT_FSIZE).
// The free space of the file system, and what the file size limit (ulimit -f) still lets the file grow by.
struct Room {
  std::uint64_t disk = UINT64_MAX;
  std::uint64_t limit = UINT64_MAX;
};
Room room_left(const std::filesystem::path& file, std::uint64_t file_size) {
  Room room;
  struct statvfs fs {};
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  if (::statvfs(dir.c_str(), &fs) == 0) room.disk = static_cast<std::uint64_t>(fs.f_bavail) * fs.f_frsize;
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    room.limit = limit.rlim_cur > file_size ? limit.rlim_cur - file_size : 0;
  return room;
}

// What the file keeps free for its metadata, the summary and the close.
constexpr std::uint64_t kReserveBytes = 1u << 20;

Handle string_type(std::size_t length) {
  Handle t(check(H5Tcopy(H5T_C_S1), "H5Tcopy"));
  check(H5Tset_size(t.get(), std::max<std::size_t>(1, length)), "H5Tset_size");
  check(H5Tset_cset(t.get(), H5T_CSET_UTF8), "H5Tset_cset");
  return t;
}

Handle link_properties() {
  Handle p(check(H5Pcreate(H5P_LINK_CREATE), "H5Pcreate"));
  check(H5Pset_create_intermediate_group(p.get(), 1), "H5Pset_create_intermediate_group");
  return p;
}

void string_attribute(hid_t object, const char* name, const std::string& value) {
  const Handle type = string_type(value.size());
  const Handle space(check(H5Screate(H5S_SCALAR), "H5Screate"));
  const Handle a(check(H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                       std::string("cannot create the attribute ") + name));
  std::string padded = value;
  padded.resize(std::max<std::size_t>(1, value.size()), '\0');
  check(H5Awrite(a.get(), type.get(), padded.data()), std::string("cannot write the attribute ") + name);
}

void strings_attribute(hid_t object, const char* name, const std::vector<std::string>& values) {
  std::size_t length = 1;
  for (const auto& v : values) length = std::max(length, v.size());
  std::string packed(length * values.size(), '\0');
  for (std::size_t k = 0; k < values.size(); ++k) std::memcpy(&packed[k * length], values[k].data(), values[k].size());
  const Handle type = string_type(length);
  const hsize_t n = values.size();
  const Handle space(check(H5Screate_simple(1, &n, nullptr), "H5Screate_simple"));
  const Handle a(check(H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                       std::string("cannot create the attribute ") + name));
  if (n > 0) check(H5Awrite(a.get(), type.get(), packed.data()), std::string("cannot write the attribute ") + name);
}

template <typename T>
void numbers_attribute(hid_t object, const char* name, const std::vector<T>& values, hid_t memory, hid_t file) {
  const hsize_t n = values.size();
  const Handle space(n == 1 ? check(H5Screate(H5S_SCALAR), "H5Screate")
                            : check(H5Screate_simple(1, &n, nullptr), "H5Screate_simple"));
  const Handle a(check(H5Acreate2(object, name, file, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                       std::string("cannot create the attribute ") + name));
  if (n > 0) check(H5Awrite(a.get(), memory, values.data()), std::string("cannot write the attribute ") + name);
}

void real_attribute(hid_t o, const char* name, double v) {
  numbers_attribute(o, name, std::vector<double>{v}, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
}
void int_attribute(hid_t o, const char* name, std::int64_t v) {
  numbers_attribute(o, name, std::vector<std::int64_t>{v}, H5T_NATIVE_INT64, H5T_STD_I64LE);
}

// A scalar string dataset (the session file, the statistics).
void text_dataset(hid_t parent, const char* name, const std::string& text) {
  const Handle type = string_type(text.size());
  const Handle space(check(H5Screate(H5S_SCALAR), "H5Screate"));
  const Handle lcpl = link_properties();
  const Handle d(check(H5Dcreate2(parent, name, type.get(), space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
                       std::string("cannot create ") + name));
  std::string padded = text;
  padded.resize(std::max<std::size_t>(1, text.size()), '\0');
  check(H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()),
        std::string("cannot write ") + name);
}

template <typename T>
void numbers_dataset(hid_t parent, const char* name, const std::vector<T>& values, hid_t memory, hid_t file) {
  const hsize_t n = values.size();
  const Handle space(check(H5Screate_simple(1, &n, nullptr), "H5Screate_simple"));
  const Handle lcpl = link_properties();
  const Handle d(check(H5Dcreate2(parent, name, file, space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
                       std::string("cannot create ") + name));
  if (n > 0)
    check(H5Dwrite(d.get(), memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), std::string("cannot write ") + name);
}

void strings_dataset(hid_t parent, const char* name, const std::vector<std::string>& values) {
  std::size_t length = 1;
  for (const auto& v : values) length = std::max(length, v.size());
  std::string packed(length * values.size(), '\0');
  for (std::size_t k = 0; k < values.size(); ++k) std::memcpy(&packed[k * length], values[k].data(), values[k].size());
  const Handle type = string_type(length);
  const hsize_t n = values.size();
  const Handle space(check(H5Screate_simple(1, &n, nullptr), "H5Screate_simple"));
  const Handle lcpl = link_properties();
  const Handle d(check(H5Dcreate2(parent, name, type.get(), space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
                       std::string("cannot create ") + name));
  if (n > 0)
    check(H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, packed.data()),
          std::string("cannot write ") + name);
}

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

constexpr hsize_t kChunkRows = 512;

}  // namespace

const std::vector<RecordingColumn>& recording_columns() {
  static const std::vector<RecordingColumn> c = [] {
    std::vector<RecordingColumn> out;
    for (const Column& k : columns()) out.push_back(k.meta);
    return out;
  }();
  return c;
}

struct RecordingFile::Impl {
  struct Dataset {
    Handle id;
    const Column* column;
    int width;                          // values per row
    std::vector<unsigned char> buffer;  // rows not yet written
  };
  struct Device {
    std::string path;
    int dof = 0;
    hsize_t rows = 0;     // written
    hsize_t pending = 0;  // buffered
    std::vector<Dataset> datasets;
  };
  std::filesystem::path path;
  Handle file;
  Handle access;  // the file access properties (for the file descriptor)
  std::vector<Device> devices;
  std::size_t buffered = 0;
  bool closed = false;

  // The file's blocks up to `end` (bytes) allocated now, its size unchanged (fallocate, FALLOC_FL_KEEP_SIZE):
  // the writes up to there and the close cannot fail for want of space, whatever another process writes to the
  // disk meanwhile (checking the free space alone left a race: a write failing half way leaves a file that does
  // not open). full: the space is not there (the disk or the file size limit is full). A file system that
  // cannot allocate ahead (unsupported) keeps the free-space check only.
  enum class Reserve { done, full, unsupported };
  Reserve reserve(std::uint64_t end) {
    if (end <= reserved_end) return Reserve::done;
    void* handle = nullptr;
    if (H5Fget_vfd_handle(file.get(), access.get(), &handle) < 0 || handle == nullptr) return Reserve::unsupported;
    const int fd = *static_cast<int*>(handle);
    // Ahead by 4 MB: one call every few seconds, not every write; what is not there, at least `end`.
    for (const std::uint64_t want : {end + (std::uint64_t{4} << 20), end}) {
      if (::fallocate(fd, FALLOC_FL_KEEP_SIZE, 0, static_cast<off_t>(want)) == 0) {
        reserved_end = want;
        return Reserve::done;
      }
      if (errno != ENOSPC && errno != EFBIG) return Reserve::unsupported;  // (EOPNOTSUPP: the free space tells)
    }
    return Reserve::full;
  }
  std::uint64_t reserved_end = 0;

  void drop_buffered() {
    for (Device& d : devices) {
      d.pending = 0;
      for (Dataset& s : d.datasets) s.buffer.clear();
    }
    buffered = 0;
  }
  void set_rows(Device& d, hsize_t rows) {
    for (Dataset& s : d.datasets) {
      const hsize_t dims[2] = {rows, static_cast<hsize_t>(s.width)};
      check(H5Dset_extent(s.id.get(), dims), "cannot extend " + d.path + "/" + s.column->meta.path);
    }
  }
};

RecordingFile::RecordingFile(const std::filesystem::path& file, const RecordingHeader& header)
    : impl_(std::make_unique<Impl>()) {
  quiet();  // errors are reported through exceptions, never printed
  Impl& m = *impl_;
  m.path = file;
  m.access = Handle(check(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate"));
  // The metadata cache (the chunk indexes, which grow with the file) at most 4 MiB: HDF5's adaptive default grows to
  // 32 MiB, and a long recording's server grew about 2 MB a minute until it did (the soak, docs/measurements.md).
  H5AC_cache_config_t cache{};
  cache.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  check(H5Pget_mdc_config(m.access.get(), &cache), "H5Pget_mdc_config");
  cache.set_initial_size = true;
  cache.initial_size = 1u << 20;
  cache.min_size = 1u << 20;
  cache.max_size = 4u << 20;
  check(H5Pset_mdc_config(m.access.get(), &cache), "H5Pset_mdc_config");
  errno = 0;
  m.file = Handle(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, m.access.get()));
  if (m.file.get() < 0) fail("cannot create the recording " + file.string());
  const hid_t root = m.file.get();
  string_attribute(root, "format", kRecordingFormat);
  int_attribute(root, "version", kRecordingVersion);
  real_attribute(root, "rate_hz", header.rate_hz);
  string_attribute(root, "clock", header.lockstep ? "lockstep" : "realtime");
  string_attribute(root, "created_utc", utc_now());
  string_attribute(root, "source", header.source);
  text_dataset(root, "session/file", header.session_text);
  {
    const Handle session(check(H5Oopen(root, "session", H5P_DEFAULT), "H5Oopen session"));
    string_attribute(session.get(), "path", header.session_file);
  }
  const Handle lcpl = link_properties();
  std::vector<std::string> names;
  for (const RecordingDevice& rd : header.devices) names.push_back(rd.name);
  strings_attribute(root, "devices", names);
  for (const RecordingDevice& rd : header.devices) {
    Impl::Device d;
    d.path = "/devices/" + rd.name;
    d.dof = rd.description.dof();
    const Handle g(
        check(H5Gcreate2(root, d.path.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), "cannot create " + d.path));
    const DeviceDescription& desc = rd.description;
    string_attribute(g.get(), "model", desc.model);
    int_attribute(g.get(), "dof", desc.dof());
    std::vector<std::string> joint_names;
    std::vector<double> qmin, qmax, vmax, peak, continuous;
    for (const JointDescription& j : desc.joints) {
      joint_names.push_back(j.name);
      qmin.push_back(j.position_min);
      qmax.push_back(j.position_max);
      vmax.push_back(j.velocity_max);
      peak.push_back(j.torque_peak_nm);
      continuous.push_back(j.torque_continuous_nm);
    }
    strings_attribute(g.get(), "joint_names", joint_names);
    numbers_attribute(g.get(), "position_min", qmin, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
    numbers_attribute(g.get(), "position_max", qmax, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
    numbers_attribute(g.get(), "velocity_max", vmax, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
    numbers_attribute(g.get(), "torque_peak", peak, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
    numbers_attribute(g.get(), "torque_continuous", continuous, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
    string_attribute(g.get(), "handle_frame", desc.handle_frame);
    string_attribute(g.get(), "interface", to_string(desc.interface));
    string_attribute(g.get(), "sensor_frame", desc.sensor_frame);
    // Absolute: a relative path is the server's working directory's, which a reader does not know.
    string_attribute(g.get(), "robot_model_file",
                     desc.robot_model_file.empty()
                         ? std::string()
                         : std::filesystem::absolute(desc.robot_model_file).lexically_normal().string());
    int_attribute(g.get(), "simulated", desc.simulated ? 1 : 0);
    const Pose& b = desc.base_pose;
    numbers_attribute(g.get(), "base_pose",
                      std::vector<double>{b.position.x(), b.position.y(), b.position.z(), b.orientation.w(),
                                          b.orientation.x(), b.orientation.y(), b.orientation.z()},
                      H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
    strings_attribute(g.get(), "schemes", rd.schemes);
    strings_attribute(g.get(), "mode_names", {kDeviceModeNames.begin(), kDeviceModeNames.end()});
    strings_attribute(g.get(), "flag_names", {kStateFlagNames.begin(), kStateFlagNames.end()});
    std::vector<std::string> column_paths;
    for (const Column& c : columns()) column_paths.emplace_back(c.meta.path);
    strings_attribute(g.get(), "columns", column_paths);  // the per-cycle datasets, in the schema's order
    for (const Column& c : columns()) {
      Impl::Dataset s;
      s.column = &c;
      s.width = c.meta.width == 0 ? std::max(1, d.dof) : c.meta.width;
      const bool vector = c.meta.width == 1;
      const hsize_t dims[2] = {0, static_cast<hsize_t>(s.width)};
      const hsize_t max[2] = {H5S_UNLIMITED, static_cast<hsize_t>(s.width)};
      const hsize_t chunk[2] = {kChunkRows, static_cast<hsize_t>(s.width)};
      const int rank = vector ? 1 : 2;
      const Handle space(check(H5Screate_simple(rank, dims, max), "H5Screate_simple"));
      const Handle dcpl(check(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate"));
      check(H5Pset_chunk(dcpl.get(), rank, chunk), "H5Pset_chunk");
      const std::string name = std::string(c.meta.path);
      // No chunk cache: every write goes to the file at once, so the file's size says what it holds (the room
      // check in write()) and a flush has little to do.
      const Handle dapl(check(H5Pcreate(H5P_DATASET_ACCESS), "H5Pcreate"));
      check(H5Pset_chunk_cache(dapl.get(), 0, 0, 1.0), "H5Pset_chunk_cache");
      s.id = Handle(check(
          H5Dcreate2(g.get(), name.c_str(), file_type(c.meta.type), space.get(), lcpl.get(), dcpl.get(), dapl.get()),
          "cannot create " + d.path + "/" + name));
      string_attribute(s.id.get(), "unit", c.meta.unit);
      string_attribute(s.id.get(), "description", c.meta.text);
      d.datasets.push_back(std::move(s));
    }
    m.devices.push_back(std::move(d));
  }
  flush();
}

RecordingFile::~RecordingFile() {
  try {
    close();
  } catch (...) {
  }
}

void RecordingFile::add(const CycleRecord& r) {
  Impl& m = *impl_;
  if (r.device >= m.devices.size()) return;
  Impl::Device& d = m.devices[r.device];
  CycleRecord padded = r;
  padded.dof = static_cast<std::uint8_t>(std::max(1, d.dof));
  for (Impl::Dataset& s : d.datasets) {
    const std::size_t row_bytes = static_cast<std::size_t>(s.width) * type_size(s.column->meta.type);
    const std::size_t at = s.buffer.size();
    s.buffer.resize(at + row_bytes);
    s.column->extract(padded, s.buffer.data() + at);
  }
  ++d.pending;
  ++m.buffered;
}

std::size_t RecordingFile::buffered() const noexcept { return impl_->buffered; }

void RecordingFile::write() {
  quiet();
  Impl& m = *impl_;
  // Stop before the file system (or the file size limit) is full, while the file can still be closed whole: a
  // write that fails half way leaves an HDF5 file that does not open.
  std::uint64_t need = kReserveBytes;
  for (const Impl::Device& d : m.devices)
    for (const Impl::Dataset& s : d.datasets) {
      const std::uint64_t chunk = kChunkRows * static_cast<std::uint64_t>(s.width) * type_size(s.column->meta.type);
      need += (s.buffer.size() / chunk + 2) * chunk;  // whole chunks, the one begun and the next
    }
  hsize_t size = 0;
  if (H5Fget_filesize(m.file.get(), &size) >= 0) {
    const Room room = room_left(m.path, size);
    // The file size limit is checked apart: an allocation ahead does not count against it, the writes do.
    const Impl::Reserve reserved = room.limit < need ? Impl::Reserve::full : m.reserve(size + need);
    if (reserved == Impl::Reserve::full || (reserved == Impl::Reserve::unsupported && room.disk < need)) {
      m.drop_buffered();
      throw std::runtime_error("cannot write the recording " + m.path.string() + ": the disk (or the file size " +
                               "limit) is nearly full (" + std::to_string(std::min(room.disk, room.limit) / 1024) +
                               " kB left): the file is complete up to here");
    }
  }
  std::size_t device = 0;
  try {
    for (device = 0; device < m.devices.size(); ++device) {
      Impl::Device& d = m.devices[device];
      if (d.pending == 0) continue;
      m.set_rows(d, d.rows + d.pending);
      for (Impl::Dataset& s : d.datasets) {
        const hsize_t start[2] = {d.rows, 0};
        const hsize_t count[2] = {d.pending, static_cast<hsize_t>(s.width)};
        const int rank = s.column->meta.width == 1 ? 1 : 2;
        const Handle file_space(check(H5Dget_space(s.id.get()), "H5Dget_space"));
        check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
              "H5Sselect_hyperslab");
        const Handle memory_space(check(H5Screate_simple(rank, count, nullptr), "H5Screate_simple"));
        errno = 0;
        check(H5Dwrite(s.id.get(), memory_type(s.column->meta.type), memory_space.get(), file_space.get(), H5P_DEFAULT,
                       s.buffer.data()),
              "cannot write " + d.path + "/" + s.column->meta.path);
        s.buffer.clear();
      }
      d.rows += d.pending;
      d.pending = 0;
    }
    m.buffered = 0;
  } catch (...) {
    // Keep whole records: every dataset of this device back to the rows written before; drop the buffers.
    if (device < m.devices.size()) {
      try {
        m.set_rows(m.devices[device], m.devices[device].rows);
      } catch (...) {
      }
    }
    m.drop_buffered();
    throw;
  }
}

void RecordingFile::flush() {
  quiet();
  Impl& m = *impl_;
  errno = 0;
  check(H5Fflush(m.file.get(), H5F_SCOPE_GLOBAL), "cannot write the recording " + m.path.string());
  void* handle = nullptr;
  if (H5Fget_vfd_handle(m.file.get(), m.access.get(), &handle) >= 0 && handle != nullptr) {
    const int fd = *static_cast<int*>(handle);
    if (::fdatasync(fd) != 0 && errno != EINVAL && errno != EROFS) fail("cannot sync the recording " + m.path.string());
  }
}

void RecordingFile::write_summary(const std::string& statistics_json, const std::vector<RecordingEvent>& events) {
  quiet();
  Impl& m = *impl_;
  const hid_t root = m.file.get();
  text_dataset(root, "statistics", statistics_json);
  std::vector<std::string> device, kind, code;
  std::vector<std::uint64_t> cycle;
  std::vector<double> time;
  for (const RecordingEvent& e : events) {
    device.push_back(e.device);
    kind.push_back(e.kind);
    code.push_back(e.code);
    cycle.push_back(e.cycle);
    time.push_back(e.time_s);
  }
  strings_dataset(root, "events/device", device);
  strings_dataset(root, "events/kind", kind);
  strings_dataset(root, "events/code", code);
  numbers_dataset(root, "events/cycle", cycle, H5T_NATIVE_UINT64, H5T_STD_U64LE);
  numbers_dataset(root, "events/time_s", time, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
  flush();
}

void RecordingFile::close() {
  quiet();
  Impl& m = *impl_;
  if (m.closed) return;
  m.closed = true;
  for (Impl::Device& d : m.devices) d.datasets.clear();
  m.access = Handle();
  errno = 0;
  check(H5Fclose(m.file.release()), "cannot close the recording " + m.path.string());
}

std::uint64_t RecordingFile::rows(std::size_t device) const { return impl_->devices.at(device).rows; }

std::string recording_name_problem(const std::filesystem::path& file) {
  const std::string extension = file.extension().string();
  if (extension == ".h5" || extension == ".hdf5") return {};
  std::string hint;
  if (extension == ".csv")
    hint = "; for CSV record to " + std::filesystem::path(file).replace_extension(".h5").string() +
           ", then hapticctl export it with --csv";
  return file.string() + ": a recording is an HDF5 file, named .h5 or .hdf5" + hint;
}

}  // namespace hapticd::recording
