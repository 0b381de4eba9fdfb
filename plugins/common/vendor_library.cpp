#include "vendor_library.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace hapticd::plugins {
namespace {

namespace fs = std::filesystem;

// Where to try, in order: full paths for the session's path and the variable's folders, bare names for the
// loader's own search.
std::vector<std::string> candidates(const VendorLibrarySearch& s) {
  std::vector<std::string> out;
  const auto in_folder = [&](const fs::path& folder) {
    for (const std::string& n : s.names) out.push_back((folder / n).string());
  };
  if (!s.path.empty()) {  // the session's choice is the only place: never another library than the one named
    std::error_code ec;
    if (fs::is_directory(s.path, ec))
      in_folder(s.path);
    else
      out.push_back(s.path);
    return out;
  }
  if (!s.environment.empty()) {
    if (const char* root = std::getenv(s.environment.c_str()); root != nullptr && root[0] != '\0') {
      in_folder(root);
      for (const std::string& sub : s.subdirs) in_folder(fs::path(root) / sub);
    }
  }
  for (const std::string& n : s.names) out.push_back(n);
  return out;
}

}  // namespace

VendorLibrary::VendorLibrary(const VendorLibrarySearch& search) : vendor_(search.vendor) {
  std::string tried;
  for (const std::string& candidate : candidates(search)) {
    dlerror();
    handle_ = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle_ != nullptr) {
      file_ = candidate;
      return;
    }
    const char* why = dlerror();
    tried += "\n  " + candidate + ": " + (why != nullptr ? why : "not loaded");
  }
  std::string where = search.path.empty() ? std::string() : "the session's path '" + search.path + "', ";
  if (!search.environment.empty()) where += "$" + search.environment + ", ";
  throw VendorLibraryError("the " + vendor_ + " library was not found (looked in " + where +
                           "then the library path; install the vendor's SDK, see docs/devices.md). Tried:" + tried);
}

VendorLibrary::~VendorLibrary() {
  if (handle_ != nullptr) dlclose(handle_);
}

void* VendorLibrary::symbol(const char* name, bool required) const {
  dlerror();
  void* p = dlsym(handle_, name);
  if (p == nullptr && required)
    throw VendorLibraryError("the " + vendor_ + " library " + file_ + " has no function " + name +
                             " (an SDK older than the plugin needs? docs/devices.md)");
  return p;
}

}  // namespace hapticd::plugins
