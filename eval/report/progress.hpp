#pragma once
// A progress bar on standard error for the long runs: "[#######.......]  12/60  rac-kp10000: 12 Hz", redrawn
// in place on a terminal; elsewhere (a log, CI) one line per tenth of the work, so logs stay short.
#include <cstddef>
#include <string>

namespace hapticd::eval {

class Progress {
 public:
  Progress(std::string title, std::size_t total);
  ~Progress();  // ends the line
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // One more unit done; `what` says what it was.
  void advance(const std::string& what);

 private:
  std::string title_;
  std::size_t total_, done_ = 0, last_tenth_ = 0;
  bool terminal_;
};

}  // namespace hapticd::eval
