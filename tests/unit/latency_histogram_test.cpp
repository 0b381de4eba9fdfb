#include "executor/latency_histogram.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "executor/cycle_statistics.hpp"

namespace hapticd::server {
namespace {

TEST(LatencyHistogram, BucketsCoverEveryValueInOrder) {
  for (int b = 0; b + 1 < LatencyHistogram::kBuckets; ++b) {
    ASSERT_EQ(LatencyHistogram::upper_edge(b) + 1, LatencyHistogram::lower_edge(b + 1)) << b;
    ASSERT_EQ(LatencyHistogram::bucket_of(LatencyHistogram::lower_edge(b)), b);
    ASSERT_EQ(LatencyHistogram::bucket_of(LatencyHistogram::upper_edge(b)), b);
  }
  EXPECT_EQ(LatencyHistogram::bucket_of(-5), 0);
  EXPECT_EQ(LatencyHistogram::bucket_of(std::int64_t{1} << 50), LatencyHistogram::kBuckets - 1);
}

TEST(LatencyHistogram, QuantilesMatchSortedSamplesWithinResolution) {
  std::mt19937_64 rng(7);
  std::lognormal_distribution<double> dist(10.0, 1.0);  // around 22 us, long tail
  std::vector<std::int64_t> samples(20000);
  LatencyHistogram h;
  for (auto& s : samples) {
    s = static_cast<std::int64_t>(dist(rng));
    h.record(s);
  }
  std::sort(samples.begin(), samples.end());
  for (double q : {0.5, 0.9, 0.99, 0.999}) {
    const auto exact = samples[static_cast<std::size_t>(std::ceil(q * samples.size())) - 1];
    const auto reported = h.quantile_ns(q);
    EXPECT_GE(reported, exact) << q;                   // never understates
    EXPECT_LE(reported, exact + exact / 64 + 1) << q;  // within one bucket (1/64 relative)
  }
  EXPECT_EQ(h.min_ns(), samples.front());
  EXPECT_EQ(h.max_ns(), samples.back());
  EXPECT_EQ(h.quantile_ns(1.0), samples.back());
  EXPECT_EQ(h.count(), samples.size());
}

TEST(LatencyHistogram, MergedHistogramsEqualOneOverAllSamples) {
  std::mt19937_64 rng(11);
  std::lognormal_distribution<double> dist(10.0, 1.0);
  LatencyHistogram a, b, all;
  for (int i = 0; i < 5000; ++i) {
    const auto v = static_cast<std::int64_t>(dist(rng));
    (i % 3 == 0 ? a : b).record(v);
    all.record(v);
  }
  a.merge(b);
  EXPECT_EQ(a.count(), all.count());
  EXPECT_EQ(a.min_ns(), all.min_ns());
  EXPECT_EQ(a.max_ns(), all.max_ns());
  EXPECT_DOUBLE_EQ(a.mean_ns(), all.mean_ns());
  for (double q : {0.1, 0.5, 0.99}) EXPECT_EQ(a.quantile_ns(q), all.quantile_ns(q)) << q;
  EXPECT_EQ(a.nonempty_buckets(), all.nonempty_buckets());
}

TEST(CycleStatistics, CountsOverrunsAndLongestRun) {
  CycleStatistics s;
  for (bool overrun : {false, true, true, false, true, true, true, false}) s.record(1000, 500, overrun);
  EXPECT_EQ(s.cycles, 8u);
  EXPECT_EQ(s.overruns, 5u);
  EXPECT_EQ(s.max_consecutive_overruns, 3u);
  EXPECT_EQ(s.compute_time.quantile_ns(0.5), 500);
}

TEST(CycleStatistics, JsonHasPercentilesAndHistogram) {
  LatencyHistogram h;
  h.record(1000);
  h.record(3000);
  const std::string json = histogram_json(h);
  EXPECT_NE(json.find("\"count\": 2"), std::string::npos) << json;
  EXPECT_NE(json.find("\"max\": 3.000"), std::string::npos) << json;
  EXPECT_NE(json.find("\"histogram\": [[1.000, 1], [2.976, 1]]"), std::string::npos) << json;
}

}  // namespace
}  // namespace hapticd::server
