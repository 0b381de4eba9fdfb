#include "executor/cycle_statistics.hpp"

#include <fmt/format.h>

namespace hapticd::server {
namespace {
double us(std::int64_t ns) { return static_cast<double>(ns) * 1e-3; }
}  // namespace

std::string histogram_json(const LatencyHistogram& h) {
  std::string out = fmt::format(
      "{{\"count\": {}, \"min\": {:.3f}, \"mean\": {:.3f}, \"p50\": {:.3f}, \"p90\": {:.3f}, \"p99\": {:.3f}, "
      "\"p999\": {:.3f}, \"max\": {:.3f}, \"histogram\": [",
      h.count(), us(h.min_ns()), h.mean_ns() * 1e-3, us(h.quantile_ns(0.5)), us(h.quantile_ns(0.9)),
      us(h.quantile_ns(0.99)), us(h.quantile_ns(0.999)), us(h.max_ns()));
  bool first = true;
  for (const auto& [lower, count] : h.nonempty_buckets()) {
    out += fmt::format("{}[{:.3f}, {}]", first ? "" : ", ", us(lower), count);
    first = false;
  }
  return out + "]}";
}

std::string histogram_summary(const LatencyHistogram& h) {
  return fmt::format("min {:.2f} us, p50 {:.2f} us, p99 {:.2f} us, p99.9 {:.2f} us, max {:.2f} us", us(h.min_ns()),
                     us(h.quantile_ns(0.5)), us(h.quantile_ns(0.99)), us(h.quantile_ns(0.999)), us(h.max_ns()));
}

}  // namespace hapticd::server
