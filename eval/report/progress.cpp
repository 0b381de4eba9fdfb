#include "progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace hapticd::eval {

Progress::Progress(std::string title, std::size_t total)
    : title_(std::move(title)), total_(std::max<std::size_t>(total, 1)), terminal_(isatty(STDERR_FILENO) == 1) {
  fmt::print(stderr, "{}: {} runs\n", title_, total_);
}

Progress::~Progress() {
  if (terminal_) fmt::print(stderr, "\n");
}

void Progress::advance(const std::string& what) {
  done_ = std::min(done_ + 1, total_);
  if (terminal_) {
    constexpr std::size_t kWidth = 30;
    const std::size_t filled = kWidth * done_ / total_;
    fmt::print(stderr, "\r[{}{}] {:>4}/{} {:<40.40}", std::string(filled, '#'), std::string(kWidth - filled, '.'),
               done_, total_, what);
    std::fflush(stderr);
    return;
  }
  const std::size_t tenth = 10 * done_ / total_;
  if (tenth > last_tenth_ || done_ == total_) {
    last_tenth_ = tenth;
    fmt::print(stderr, "  {:>3}% ({}/{}) {}\n", 100 * done_ / total_, done_, total_, what);
  }
}

}  // namespace hapticd::eval
