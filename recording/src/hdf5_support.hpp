#pragma once
// The recording's HDF5 plumbing, shared by its writer (recording_file.cpp) and readers (recording_reader.cpp,
// recording_export.cpp): a handle that closes any HDF5 object, errors as exceptions with HDF5's own message, the
// library kept quiet, and reading attributes. Only those files include this (and so hdf5.h).
#include <hdf5.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace hapticd::hdf5 {

// HDF5 keeps its error-printing setting per thread: every entry point calls this first. The library's own
// clean-up at exit is off too: it closes the files still open, and a file whose close failed (a write error)
// crashes it there; the process's end closes the file descriptor either way.
inline void quiet() {
  static const bool no_atexit = [] { return H5dont_atexit() >= 0; }();
  (void)no_atexit;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

// Throws what failed, with errno's text when set and the innermost HDF5 error's description.
[[noreturn]] inline void fail(const std::string& what) {
  std::string detail;
  const int saved_errno = errno;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned n, const H5E_error2_t* e, void* text) -> herr_t {
        if (n == 0 && e->desc != nullptr) *static_cast<std::string*>(text) = e->desc;
        return 0;
      },
      &detail);
  H5Eclear2(H5E_DEFAULT);
  std::string message = what;
  if (saved_errno != 0) message += std::string(": ") + std::strerror(saved_errno);
  if (!detail.empty()) message += " (HDF5: " + detail + ")";
  throw std::runtime_error(message);
}

// An HDF5 call's result, or fail(what) when it reports an error (negative).
template <typename T>
T check(T value, const std::string& what) {
  if (value < 0) fail(what);
  return value;
}

// Closes any HDF5 object when it goes out of scope.
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, -1)) {}
  Handle& operator=(Handle&& o) noexcept {
    std::swap(id_, o.id_);
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0) (void)H5Idec_ref(id_);  // closes the object, whatever its kind, at the last reference
  }
  [[nodiscard]] hid_t get() const noexcept { return id_; }
  hid_t release() noexcept { return std::exchange(id_, -1); }

 private:
  hid_t id_ = -1;
};

// ---- reading ----

// A text attribute (fixed-length, NUL-padded as the writer stores them).
inline std::string read_string_attribute(hid_t object, const char* name) {
  Handle a(check(H5Aopen(object, name, H5P_DEFAULT), std::string("no attribute ") + name));
  Handle type(check(H5Aget_type(a.get()), "H5Aget_type"));
  const std::size_t size = H5Tget_size(type.get());
  std::string value(size, '\0');
  if (H5Aread(a.get(), type.get(), value.data()) < 0) fail(std::string("cannot read ") + name);
  value.resize(std::strlen(value.c_str()));
  return value;
}

// An attribute of several texts.
inline std::vector<std::string> read_strings_attribute(hid_t object, const char* name) {
  Handle a(check(H5Aopen(object, name, H5P_DEFAULT), std::string("no attribute ") + name));
  Handle type(check(H5Aget_type(a.get()), "H5Aget_type"));
  Handle space(check(H5Aget_space(a.get()), "H5Aget_space"));
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  const std::size_t size = H5Tget_size(type.get());
  std::string packed(size * static_cast<std::size_t>(std::max<hssize_t>(n, 0)), '\0');
  if (n > 0 && H5Aread(a.get(), type.get(), packed.data()) < 0) fail(std::string("cannot read ") + name);
  std::vector<std::string> out;
  for (hssize_t k = 0; k < n; ++k) {
    std::string v = packed.substr(static_cast<std::size_t>(k) * size, size);
    v.resize(std::strlen(v.c_str()));
    out.push_back(v);
  }
  return out;
}

// A numeric attribute as doubles (HDF5 converts integers).
inline std::vector<double> read_numbers_attribute(hid_t object, const char* name) {
  Handle a(check(H5Aopen(object, name, H5P_DEFAULT), std::string("no attribute ") + name));
  Handle space(check(H5Aget_space(a.get()), "H5Aget_space"));
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  std::vector<double> values(static_cast<std::size_t>(std::max<hssize_t>(n, 0)));
  if (n > 0 && H5Aread(a.get(), H5T_NATIVE_DOUBLE, values.data()) < 0) fail(std::string("cannot read ") + name);
  return values;
}

// A hapticd recording opened to read; throws when the file does not open or is not one.
inline Handle open_recording(const std::string& file) {
  quiet();
  // A FIFO or a device would block or stream without end: regular files only.
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (ec || !std::filesystem::exists(status)) throw std::runtime_error("cannot open " + file + ": no such file");
  if (!std::filesystem::is_regular_file(status)) throw std::runtime_error(file + ": not a regular file");
  errno = 0;  // what fail() reports is this call's
  Handle f(check(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "cannot open " + file));
  if (H5Aexists(f.get(), "format") <= 0 || read_string_attribute(f.get(), "format") != "hapticd-recording")
    throw std::runtime_error(file + " is not a hapticd recording (no format attribute 'hapticd-recording')");
  return f;
}

}  // namespace hapticd::hdf5
