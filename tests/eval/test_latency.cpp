// Latency summaries: the nearest-rank percentile against its definition, counted by brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <vector>

#include "loopscan/eval/latency.hpp"

namespace loopscan::eval {
namespace {

TEST(Latency, PercentileIsTheSmallestSampleWithThatShareAtOrBelowIt) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 60);
    std::vector<double> samples;
    // Few distinct values: ties are the hard case.
    for (int i = 0; i < n; ++i) samples.push_back(static_cast<double>(rng() % 12));
    for (double p : {0.01, 0.25, 0.5, 0.9, 0.99, 1.0}) {
      const double got = percentile(samples, p);
      // The definition: the smallest sample value v with #{x <= v} >= p n.
      double expected = 1e300;
      for (double v : samples) {
        const auto at_or_below =
            std::count_if(samples.begin(), samples.end(), [&](double x) { return x <= v; });
        if (static_cast<double>(at_or_below) >= p * n - 1e-9) expected = std::min(expected, v);
      }
      ASSERT_EQ(got, expected) << "n " << n << " p " << p;
    }
  }
}

TEST(Latency, SummaryOfAHundredCalls) {
  std::vector<double> ms;
  for (int i = 1; i <= 100; ++i) ms.push_back(i);
  std::shuffle(ms.begin(), ms.end(), std::mt19937(1));
  const LatencySummary s = summarise_latency(ms);
  EXPECT_EQ(s.count, 100);
  EXPECT_EQ(s.p50_ms, 50);
  EXPECT_EQ(s.p99_ms, 99);
  EXPECT_EQ(s.max_ms, 100);
  EXPECT_EQ(summarise_latency({}).count, 0);
  EXPECT_EQ(summarise_latency({}).p99_ms, 0);
  EXPECT_EQ(percentile({7}, 0.01), 7);
  EXPECT_THROW(percentile({1, 2}, 0), std::invalid_argument);
  EXPECT_THROW(percentile({1, 2}, 1.5), std::invalid_argument);
}

}  // namespace
}  // namespace loopscan::eval
