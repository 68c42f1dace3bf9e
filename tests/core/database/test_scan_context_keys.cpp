// The Scan Context index keys (scan_context_store.hpp) against their straightforward definitions,
// at every SIMD width the machine has (LOOPSCAN_NO_AVX2=1 for the baseline).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "loopscan/core/database/key_scan.hpp"
#include "loopscan/core/database/scan_context_store.hpp"

namespace loopscan {
namespace {

TEST(ScanContextKeys, SpectralKeyDistanceIsTheExactSquaredDistance) {
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> value(0, 65535), pick(0, 3);
  for (std::size_t n : {0u, 1u, 15u, 16u, 17u, 33u, 120u, 240u}) {
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<std::uint16_t> a(n), b(n);
      for (std::size_t t = 0; t < n; ++t) {
        // Extremes often: the largest squares must not wrap.
        const int k = pick(rng);
        a[t] = static_cast<std::uint16_t>(k == 0 ? 0 : k == 1 ? 65535 : value(rng));
        b[t] = static_cast<std::uint16_t>(k == 0 ? 65535 : k == 1 ? 0 : value(rng));
      }
      std::uint64_t want = 0;
      for (std::size_t t = 0; t < n; ++t) {
        const std::int64_t d = std::int64_t{a[t]} - std::int64_t{b[t]};
        want += static_cast<std::uint64_t>(d * d);
      }
      EXPECT_EQ(spectral_key_distance(a.data(), b.data(), n), want) << "n " << n;
      EXPECT_EQ(spectral_key_distance(b.data(), a.data(), n), want) << "n " << n;
    }
  }
}

TEST(ScanContextKeys, CoarseKeyAveragesTheDcTermsOfRingGroups) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> value(0, 65535);
  for (int rings : {1, 20, 32, 33, 40}) {
    const int per_ring = 1 + kSpectralKeyFrequencies;
    std::vector<std::uint16_t> key(2 * rings * per_ring);
    for (auto& v : key) v = static_cast<std::uint16_t>(value(rng));
    // Layout: R structure DC terms, R x F structure harmonics, then per intensity ring its DC
    // term and harmonics.
    auto dc = [&](int half, int r) {
      return half == 0 ? key[r] : key[rings * per_ring + per_ring * r];
    };
    const int group = (2 * rings + KeyScan::kMaxDims - 1) / KeyScan::kMaxDims;
    std::vector<std::uint16_t> want;
    for (int half = 0; half < 2; ++half) {
      for (int r0 = 0; r0 < rings; r0 += group) {
        std::uint64_t sum = 0;
        int members = 0;
        for (int r = r0; r < rings && r < r0 + group; ++r, ++members) sum += dc(half, r);
        want.push_back(static_cast<std::uint16_t>(sum / members / 8));
      }
    }
    EXPECT_EQ(coarse_key(key, rings), want) << rings;
    EXPECT_EQ(coarse_key_dims(rings), static_cast<int>(want.size())) << rings;
    EXPECT_LE(coarse_key_dims(rings), KeyScan::kMaxDims);
  }
}

}  // namespace
}  // namespace loopscan
