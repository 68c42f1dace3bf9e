// The packing's accumulation at the machine's SIMD width against the scalar loop, bit for bit
// (a fused multiply-add in a clone would change the last bits of most sums).
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "loopscan/core/matching/scaled_accumulate.hpp"

namespace loopscan {
namespace {

TEST(ScaledAccumulate, EqualsTheScalarLoopBitForBit) {
  std::mt19937 rng(5);
  std::normal_distribution<float> g;
  for (int n = 0; n <= 70; ++n) {
    std::vector<float> row(n), got(n + 1), want(n + 1);
    for (float& x : row) x = g(rng);
    for (int i = 0; i <= n; ++i) got[i] = want[i] = g(rng);
    for (int step = 0; step < 3; ++step) {
      const float v = g(rng);
      scaled_accumulate(got.data(), row.data(), v, n);
      for (int k = 0; k < n; ++k) {
        const float p = v * row[k];  // rounded to float before the sum, as the kernel does
        want[k] = want[k] + p;
      }
    }
    EXPECT_EQ(std::memcmp(got.data(), want.data(), sizeof(float) * (n + 1)), 0) << "n " << n;
  }
}

}  // namespace
}  // namespace loopscan
