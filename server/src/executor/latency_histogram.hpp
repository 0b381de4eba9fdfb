#pragma once
// Log-linear histogram of durations in nanoseconds: exact below 128 ns, then 64 buckets per power of two
// (relative resolution 1.6%), up to about 18 minutes. Fixed storage; record() is real-time safe.
#include <array>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace hapticd::server {

class LatencyHistogram {
 public:
  static constexpr int kExact = 128;
  static constexpr int kSubBuckets = 64;
  static constexpr int kOctaves = 34;
  static constexpr int kBuckets = kExact + kOctaves * kSubBuckets;

  void record(std::int64_t value_ns) noexcept;
  // Adds other's samples (histograms of several sources in one).
  void merge(const LatencyHistogram& other) noexcept;

  [[nodiscard]] std::uint64_t count() const noexcept { return count_; }
  [[nodiscard]] std::int64_t min_ns() const noexcept { return count_ ? min_ : 0; }
  [[nodiscard]] std::int64_t max_ns() const noexcept { return count_ ? max_ : 0; }
  [[nodiscard]] double mean_ns() const noexcept {
    return count_ ? static_cast<double>(sum_) / static_cast<double>(count_) : 0.0;
  }
  // Value below which the fraction q (0..1) of the samples lie: the upper edge of the bucket that holds the
  // q-quantile, clamped to the exact maximum (so it never understates).
  [[nodiscard]] std::int64_t quantile_ns(double q) const noexcept;
  // (lower edge [ns], count) of every non-empty bucket.
  [[nodiscard]] std::vector<std::pair<std::int64_t, std::uint64_t>> nonempty_buckets() const;

  static int bucket_of(std::int64_t value_ns) noexcept;
  static std::int64_t lower_edge(int bucket) noexcept;
  static std::int64_t upper_edge(int bucket) noexcept;

 private:
  std::array<std::uint64_t, kBuckets> buckets_{};
  std::uint64_t count_ = 0;
  std::int64_t sum_ = 0;
  std::int64_t min_ = std::numeric_limits<std::int64_t>::max();
  std::int64_t max_ = 0;
};

}  // namespace hapticd::server
