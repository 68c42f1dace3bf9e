// The multi-query key scan against brute force over the same distance, at every SIMD width the
// machine has (run the suite with LOOPSCAN_NO_AVX512=1 / LOOPSCAN_NO_AVX2=1 for the others).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "loopscan/core/database/key_scan.hpp"

namespace loopscan {
namespace {

TEST(KeyScan, NearestOfEveryQueryEqualsBruteForceAmongEligible) {
  for (int dims : {1, 10, 17}) {
    for (std::size_t n : {0u, 1u, 15u, 16u, 17u, 100u, 2049u}) {
      std::mt19937 rng(static_cast<unsigned>(dims * 10007 + n));
      // Coarse values make exact ties common: they must go to the smaller index.
      std::uniform_int_distribution<int> level(0, 6);
      std::vector<float> data(n * dims);
      for (float& v : data) v = 0.25f * static_cast<float>(level(rng));
      KeyScan scan(dims);
      for (std::size_t i = 0; i < n; ++i) scan.add(&data[i * dims]);
      ASSERT_EQ(scan.size(), n);
      const auto eligible = [](std::size_t i) { return i % 3 != 1; };
      for (std::size_t count : {1u, 5u, 40u, 300u}) {
        const int n_queries = 5;
        std::vector<float> queries(static_cast<std::size_t>(n_queries) * dims);
        for (float& v : queries) v = 0.25f * static_cast<float>(level(rng)) + 0.01f;
        std::vector<std::vector<std::pair<float, std::size_t>>> got;
        scan.nearest(queries.data(), n_queries, count, eligible, got);
        ASSERT_EQ(got.size(), std::size_t(n_queries));
        for (int v = 0; v < n_queries; ++v) {
          std::vector<std::pair<float, std::size_t>> want;
          for (std::size_t i = 0; i < n; ++i) {
            if (!eligible(i)) continue;
            want.emplace_back(KeyScan::distance(&queries[v * dims], &data[i * dims], dims), i);
          }
          std::sort(want.begin(), want.end());
          want.resize(std::min(count, want.size()));
          EXPECT_EQ(got[v], want) << "dims " << dims << " n " << n << " count " << count;
        }
      }
    }
  }
}

TEST(KeyScan, DistanceIsTheSquaredEuclideanOne) {
  const float a[3] = {1.f, 2.f, -3.f}, b[3] = {0.f, 4.f, 1.f};
  EXPECT_FLOAT_EQ(KeyScan::distance(a, b, 3), 1.f + 4.f + 16.f);
}

}  // namespace
}  // namespace loopscan
