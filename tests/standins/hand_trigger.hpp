#pragma once
// When a stand-in's simulated hand pushes, in a run of the server: a test script has no function to call in the
// server's process, so with HAPTICD_STANDIN_HAND_WHEN naming a file the hand pushes only while that file exists
// (the script creates it once its engine holds the device). Without the variable the hand always pushes. The
// file is looked at every 50th call (a step of the physics), so the check costs nothing a test would notice.
#include <sys/stat.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace hapticd::standins {

class HandTrigger {
 public:
  [[nodiscard]] bool pushing() noexcept {
    if (calls_++ % 50 != 0) return pushing_;
    if (!read_) {
      read_ = true;
      const char* path = std::getenv("HAPTICD_STANDIN_HAND_WHEN");
      if (path != nullptr) path_ = path;
    }
    struct stat st {};
    pushing_ = path_.empty() || ::stat(path_.c_str(), &st) == 0;
    return pushing_;
  }

 private:
  unsigned calls_ = 0;
  bool read_ = false, pushing_ = true;
  std::string path_;
};

// The hand's force "fx,fy,fz" (N) from the environment variable `name` into `force`; false (force untouched)
// when the variable is not set or not three numbers.
inline bool hand_from_environment(const char* name, std::array<double, 3>& force) {
  const char* text = std::getenv(name);
  std::array<double, 3> f{0, 0, 0};
  if (text == nullptr || std::sscanf(text, "%lf,%lf,%lf", &f[0], &f[1], &f[2]) != 3) return false;
  force = f;
  return true;
}

}  // namespace hapticd::standins
