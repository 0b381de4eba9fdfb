#pragma once
// A vendor's SDK library, loaded at run time (dlopen), never linked or shipped: the device plugins of commercial
// devices (Force Dimension's libdhd/libdrd, 3D Systems' libHD) find it where the session or the machine says, take
// the functions they need by name, and say plainly what is missing. Not real-time: configure() only.
//
// Where it looks: the session's path when it gives one (a file, or a folder holding one of the names; only there,
// so a wrong path is an error, never another library), else the folders of an environment variable (the vendor's
// own, e.g. FORCEDIM_SDK, and its lib/ and lib/release/lin-x86_64-gcc/ subfolders), then the dynamic loader's own
// search (LD_LIBRARY_PATH, ld.so.conf, the system folders).
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace hapticd::plugins {

// The longest text taken from a vendor's library (a model name, a serial, an error): its strings are read only this
// far (no strlen over memory the library may not have terminated).
inline constexpr std::size_t kMaxVendorText = 200;

// A string a vendor's library returned, bounded before use: at most kMaxVendorText bytes, bytes outside printable
// ASCII written as '?'; `absent` for a null pointer. Not real-time (it allocates): in the loop, format with
// "%.200s", which reads no further either.
inline std::string vendor_text(const char* text, const char* absent = "unknown") {
  if (text == nullptr) return absent;
  std::string out;
  for (std::size_t i = 0; i < kMaxVendorText && text[i] != '\0'; ++i)
    out += (text[i] >= 0x20 && text[i] < 0x7f) ? text[i] : '?';
  return out;
}

struct VendorLibrarySearch {
  std::string vendor;                // for messages: "Force Dimension SDK"
  std::vector<std::string> names;    // file names to try, in order: "libdrd.so.3", "libdrd.so", "libdhd.so"
  std::string path;                  // the session's: a file or a folder ("" none)
  std::string environment;           // a variable naming the SDK's folder ("" none)
  std::vector<std::string> subdirs;  // below the variable's folder: "lib", "lib/release/lin-x86_64-gcc"
};

// Thrown when the library cannot be found or lacks a function: names the vendor, every place tried and why.
class VendorLibraryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class VendorLibrary {
 public:
  // Loads the first of the candidates that opens; throws VendorLibraryError naming every candidate tried.
  explicit VendorLibrary(const VendorLibrarySearch& search);
  ~VendorLibrary();
  VendorLibrary(const VendorLibrary&) = delete;
  VendorLibrary& operator=(const VendorLibrary&) = delete;

  // The function `name` as a pointer of type F (the vendor's documented prototype; the caller's responsibility).
  // Throws VendorLibraryError when the library lacks it (an SDK too old).
  template <class F>
  F function(const char* name) const {
    return reinterpret_cast<F>(symbol(name, true));
  }
  // As function(), nullptr when absent (an optional function of newer SDKs).
  template <class F>
  F optional_function(const char* name) const {
    return reinterpret_cast<F>(symbol(name, false));
  }
  // The file that was loaded.
  [[nodiscard]] const std::string& file() const noexcept { return file_; }

 private:
  void* symbol(const char* name, bool required) const;

  std::string vendor_;
  std::string file_;
  void* handle_ = nullptr;
};

}  // namespace hapticd::plugins
