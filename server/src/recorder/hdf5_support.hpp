#pragma once
// The recording's HDF5 plumbing, shared by its writer (recording_file.cpp) and reader (recording_export.cpp):
// a handle that closes any HDF5 object, errors as exceptions with HDF5's own message, and the library kept
// quiet. Only those two files include this (and so hdf5.h).
#include <hdf5.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

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

}  // namespace hapticd::hdf5
