// The multi-query key scan against brute force over the same distance, at every SIMD width the
// machine has (run the suite with LOOPSCAN_NO_AVX512=1 / LOOPSCAN_NO_AVX2=1 for the others).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
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
      std::vector<std::uint16_t> data(n * dims);
      for (auto& v : data) v = static_cast<std::uint16_t>(1000 * level(rng));
      if (n > 0) data[0] = 65535;  // clamped to KeyScan::kMaxKey
      KeyScan scan(dims);
      for (std::size_t i = 0; i < n; ++i) scan.add(&data[i * dims]);
      ASSERT_EQ(scan.size(), n);
      const auto eligible = [](std::size_t i) { return i % 3 != 1; };
      for (std::size_t count : {1u, 5u, 40u, 300u}) {
        const int n_queries = 5;
        std::vector<std::uint16_t> queries(static_cast<std::size_t>(n_queries) * dims);
        for (auto& v : queries) v = static_cast<std::uint16_t>(1000 * level(rng) + 1);
        std::vector<KeyScan::Neighbours> got;
        scan.nearest(queries.data(), n_queries, count, eligible, got);
        ASSERT_EQ(got.size(), std::size_t(n_queries));
        for (int v = 0; v < n_queries; ++v) {
          KeyScan::Neighbours want;
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

// Brute force over the same distance: the `count` nearest eligible ids, ties to the smaller.
KeyScan::Neighbours brute_force(const std::vector<std::uint16_t>& data, int dims,
                                const std::uint16_t* q, std::size_t count,
                                const std::function<bool(std::size_t)>& ok) {
  KeyScan::Neighbours want;
  for (std::size_t i = 0; i < data.size() / dims; ++i) {
    if (ok(i)) want.emplace_back(KeyScan::distance(q, &data[i * dims], dims), i);
  }
  std::sort(want.begin(), want.end());
  want.resize(std::min(count, want.size()));
  return want;
}

// Keys around a few hundred centres (like near-identical places), coarse enough for ties.
std::vector<std::uint16_t> clustered_keys(std::size_t n, int dims, std::mt19937& rng,
                                          std::size_t clusters = 300) {
  std::normal_distribution<float> g;
  std::vector<float> centres(clusters * dims);
  std::vector<std::uint16_t> data(n * dims);
  for (float& v : centres) v = 4.f * g(rng);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = rng() % clusters;
    for (int d = 0; d < dims; ++d) {
      const float v = 4000.f + 200.f * (centres[c * dims + d] + 0.3f * g(rng));
      data[i * dims + d] = static_cast<std::uint16_t>(std::clamp(std::round(v), 0.f, 8191.f));
    }
  }
  return data;
}

// Cells trained at 256 keys and each doubling after: probing every cell gives the exact answer.
TEST(KeyScan, CellsProbedWhollyEqualBruteForce) {
  const int dims = 6;
  std::mt19937 rng(3);
  const std::vector<std::uint16_t> data = clustered_keys(5000, dims, rng);
  KeyScan scan(dims, KeyScanConfig{256, 1000000});
  const auto eligible = [](std::size_t i) { return i % 5 != 2; };
  for (std::size_t i = 0; i < 5000; ++i) {
    scan.add(&data[i * dims]);
    const std::size_t n = i + 1;
    if (n != 255 && n != 256 && n != 1500 && n != 5000) continue;
    EXPECT_EQ(scan.cells() > 1, n >= 256) << n;
    const std::vector<std::uint16_t> known(data.begin(), data.begin() + n * dims);
    for (std::size_t count : {1u, 10u, 200u}) {
      std::vector<std::uint16_t> queries(3 * dims);
      for (int v = 0; v < 3; ++v) std::copy_n(&data[(rng() % n) * dims], dims, &queries[v * dims]);
      queries[0] += 3;  // off the data too
      std::vector<KeyScan::Neighbours> got;
      scan.nearest(queries.data(), 3, count, eligible, got);
      for (int v = 0; v < 3; ++v) {
        EXPECT_EQ(got[v], brute_force(known, dims, &queries[v * dims], count, eligible))
            << "n " << n << " count " << count;
      }
    }
  }
}

// With the default probing, a cell search finds nearly all of the true nearest keys, and
// what it returns is in exact order with exact distances.
TEST(KeyScan, CellSearchFindsNearlyAllTrueNeighbours) {
  const int dims = 10;
  std::mt19937 rng(4);
  const std::size_t n = 40000;
  const std::vector<std::uint16_t> data = clustered_keys(n, dims, rng, 20);
  KeyScan scan(dims, KeyScanConfig{8192, 32});
  for (std::size_t i = 0; i < n; ++i) scan.add(&data[i * dims]);
  ASSERT_GE(scan.cells(), 64u);
  const auto all = [](std::size_t) { return true; };
  double found = 0, wanted = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const std::uint16_t* q = &data[(rng() % n) * dims];
    std::vector<KeyScan::Neighbours> got;
    scan.nearest(q, 1, 100, all, got);
    const auto want = brute_force(data, dims, q, 100, all);
    ASSERT_EQ(got[0].size(), 100u);
    for (std::size_t j = 0; j < got[0].size(); ++j) {
      const auto& [d, i] = got[0][j];
      EXPECT_EQ(d, KeyScan::distance(q, &data[i * dims], dims));
      if (j > 0) {
        EXPECT_LE(got[0][j - 1], got[0][j]);
      }
    }
    for (const auto& w : want) {
      found += std::count(got[0].begin(), got[0].end(), w);
      ++wanted;
    }
  }
  EXPECT_GE(found / wanted, 0.95) << "recall " << found / wanted;
}

// The pilot scan (every 8th block) sets a bound that about 2 count places should lie within.
// Here the near places are all in the pilot's blocks, so its bound holds too few of them: the
// search must notice and scan again without it.
TEST(KeyScan, PilotBoundTooTightIsNoticed) {
  const int dims = 4;
  const std::size_t n = 16 * 8 * 40, count = 150;
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> near(0, 400), far(3000, 8000);
  std::vector<std::uint16_t> data(n * dims);
  for (std::size_t i = 0; i < n; ++i) {
    const bool pilot_block = (i / KeyScan::kBlock) % 8 == 0;
    for (int d = 0; d < dims; ++d) {
      data[i * dims + d] = static_cast<std::uint16_t>(pilot_block ? near(rng) : far(rng));
    }
  }
  KeyScan scan(dims);
  for (std::size_t i = 0; i < n; ++i) scan.add(&data[i * dims]);
  ASSERT_EQ(scan.cells(), 1u);
  const auto eligible = [](std::size_t i) { return i % 3 != 1; };
  std::vector<std::uint16_t> queries = {0, 0, 0, 0, 200, 200, 200, 200, 6000, 6000, 6000, 6000};
  std::vector<KeyScan::Neighbours> got;
  scan.nearest(queries.data(), 3, count, eligible, got);
  for (int v = 0; v < 3; ++v) {
    EXPECT_EQ(got[v], brute_force(data, dims, &queries[v * dims], count, eligible)) << v;
  }
}

TEST(KeyScan, DistanceIsTheSquaredEuclideanOne) {
  const std::uint16_t a[3] = {1, 2, 9000}, b[3] = {0, 4, 8000};
  EXPECT_EQ(KeyScan::distance(a, b, 3), 1u + 4u + (8191u - 8000u) * (8191u - 8000u));
}

}  // namespace
}  // namespace loopscan
