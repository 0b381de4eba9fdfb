#include "doors/dds/cyclone_log.hpp"

#include <dds/dds.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <string_view>

namespace hapticd::server::cyclone_log {
namespace {

struct Route {
  std::mutex mutex;  // the token bucket (Cyclone's threads; never the loop)
  double lines_per_s = 5.0;
  double burst = 20.0;
  double tokens = 20.0;
  std::chrono::steady_clock::time_point refilled = std::chrono::steady_clock::now();
  std::atomic<std::uint64_t> forwarded{0};
  std::atomic<std::uint64_t> suppressed{0};
  std::atomic<std::uint64_t> reported{0};  // suppressed lines already summarised
  bool installed = false;
};

Route& route() {
  static Route r;
  return r;
}

bool take_token(Route& r) {
  std::lock_guard lock(r.mutex);
  const auto now = std::chrono::steady_clock::now();
  r.tokens = std::min(r.burst, r.tokens + r.lines_per_s * std::chrono::duration<double>(now - r.refilled).count());
  r.refilled = now;
  if (r.tokens < 1.0) return false;
  r.tokens -= 1.0;
  return true;
}

void sink(void*, const dds_log_data_t* data) {
  Route& r = route();
  if (!take_token(r)) {
    r.suppressed.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  r.forwarded.fetch_add(1, std::memory_order_relaxed);
  std::string_view text(data->message, data->size);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  const auto level = (data->priority & (DDS_LC_FATAL | DDS_LC_ERROR)) != 0 ? spdlog::level::err
                     : (data->priority & DDS_LC_WARNING) != 0              ? spdlog::level::warn
                                                                           : spdlog::level::info;
  spdlog::log(level, "Cyclone DDS: {}", text);
}

}  // namespace

void route_to_logger(double lines_per_s, double burst) {
  Route& r = route();
  {
    std::lock_guard lock(r.mutex);
    r.lines_per_s = lines_per_s;
    r.burst = std::max(1.0, burst);
    r.tokens = std::min(r.tokens, r.burst);
    if (r.installed) return;
    r.installed = true;
  }
  dds_set_log_sink(&sink, nullptr);
}

Counts counts() noexcept {
  const Route& r = route();
  return {r.forwarded.load(std::memory_order_relaxed), r.suppressed.load(std::memory_order_relaxed)};
}

void report_suppressed() {
  Route& r = route();
  const std::uint64_t total = r.suppressed.load(std::memory_order_relaxed);
  const std::uint64_t before = r.reported.exchange(total, std::memory_order_relaxed);
  if (total > before)
    spdlog::warn("Cyclone DDS: {} more log lines suppressed (rate limit {} per second; {} in all)", total - before,
                 r.lines_per_s, total);
}

}  // namespace hapticd::server::cyclone_log
