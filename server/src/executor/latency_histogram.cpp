#include "executor/latency_histogram.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace hapticd::server {

int LatencyHistogram::bucket_of(std::int64_t value_ns) noexcept {
  const auto v = static_cast<std::uint64_t>(std::max<std::int64_t>(value_ns, 0));
  if (v < static_cast<std::uint64_t>(kExact)) return static_cast<int>(v);
  const int shift = std::bit_width(v) - 7;  // >= 1: v >> shift lies in [64, 128)
  const int octave = shift - 1;
  if (octave >= kOctaves) return kBuckets - 1;
  return kExact + octave * kSubBuckets + static_cast<int>((v >> shift) - kSubBuckets);
}

std::int64_t LatencyHistogram::lower_edge(int bucket) noexcept {
  if (bucket < kExact) return bucket;
  const int octave = (bucket - kExact) / kSubBuckets;
  const int sub = (bucket - kExact) % kSubBuckets;
  return static_cast<std::int64_t>(kSubBuckets + sub) << (octave + 1);
}

std::int64_t LatencyHistogram::upper_edge(int bucket) noexcept {
  if (bucket < kExact) return bucket;
  const int octave = (bucket - kExact) / kSubBuckets;
  return lower_edge(bucket) + (std::int64_t{1} << (octave + 1)) - 1;
}

void LatencyHistogram::record(std::int64_t value_ns) noexcept {
  value_ns = std::max<std::int64_t>(value_ns, 0);
  ++buckets_[static_cast<std::size_t>(bucket_of(value_ns))];
  ++count_;
  sum_ += value_ns;
  min_ = std::min(min_, value_ns);
  max_ = std::max(max_, value_ns);
}

void LatencyHistogram::merge(const LatencyHistogram& other) noexcept {
  for (std::size_t b = 0; b < buckets_.size(); ++b) buckets_[b] += other.buckets_[b];
  count_ += other.count_;
  sum_ += other.sum_;
  min_ = std::min(min_, other.min_);
  max_ = std::max(max_, other.max_);
}

std::int64_t LatencyHistogram::quantile_ns(double q) const noexcept {
  if (count_ == 0) return 0;
  const auto rank = static_cast<std::uint64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_)));
  std::uint64_t seen = 0;
  for (int b = 0; b < kBuckets; ++b) {
    seen += buckets_[static_cast<std::size_t>(b)];
    if (seen >= std::max<std::uint64_t>(rank, 1)) return std::min(upper_edge(b), max_);
  }
  return max_;
}

std::vector<std::pair<std::int64_t, std::uint64_t>> LatencyHistogram::nonempty_buckets() const {
  std::vector<std::pair<std::int64_t, std::uint64_t>> out;
  for (int b = 0; b < kBuckets; ++b)
    if (buckets_[static_cast<std::size_t>(b)] != 0)
      out.emplace_back(lower_edge(b), buckets_[static_cast<std::size_t>(b)]);
  return out;
}

}  // namespace hapticd::server
