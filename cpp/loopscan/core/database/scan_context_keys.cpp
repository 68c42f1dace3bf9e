#include "loopscan/core/database/scan_context_keys.hpp"

#include <algorithm>

#include "loopscan/core/database/key_scan.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

// |d|^2 < 2^32 fits a uint32; the sum a uint64. Compiled for AVX2 and for the baseline.
LOOPSCAN_INLINE std::uint64_t key_distance_impl(const std::uint16_t* __restrict a,
                                                const std::uint16_t* __restrict b, std::size_t n) {
  std::uint64_t e = 0;
  for (std::size_t t = 0; t < n; ++t) {
    const std::uint32_t d = a[t] > b[t] ? a[t] - b[t] : b[t] - a[t];
    e += static_cast<std::uint64_t>(d * d);
  }
  return e;
}
std::uint64_t key_distance_base(const std::uint16_t* a, const std::uint16_t* b, std::size_t n) {
  return key_distance_impl(a, b, n);
}
LOOPSCAN_AVX2 std::uint64_t key_distance_avx2(const std::uint16_t* a, const std::uint16_t* b,
                                              std::size_t n) {
  return key_distance_impl(a, b, n);
}

int coarse_group(int rings) { return (2 * rings + KeyScan::kMaxDims - 1) / KeyScan::kMaxDims; }

}  // namespace

std::uint64_t spectral_key_distance(const std::uint16_t* a, const std::uint16_t* b, std::size_t n) {
  static const auto kernel = simd::has_avx2() ? key_distance_avx2 : key_distance_base;
  return kernel(a, b, n);
}

int coarse_key_dims(int rings) {
  const int g = coarse_group(rings);
  return 2 * ((rings + g - 1) / g);
}

std::vector<std::uint16_t> coarse_key(const std::vector<std::uint16_t>& spectral_key, int rings) {
  // Spectral key layout: the R structure DC terms, the structure harmonics (R x F), then per
  // intensity ring its DC term and harmonics.
  const int R = rings, per_ring = 1 + kSpectralKeyFrequencies, g = coarse_group(R);
  const int intensity = R + (per_ring - 1) * R;
  std::vector<std::uint16_t> out;
  for (int half = 0; half < 2; ++half) {
    for (int r0 = 0; r0 < R; r0 += g) {
      std::uint32_t sum = 0;
      const int end = std::min(R, r0 + g);
      for (int r = r0; r < end; ++r) {
        sum += half == 0 ? spectral_key[r] : spectral_key[intensity + per_ring * r];
      }
      out.push_back(static_cast<std::uint16_t>(sum / static_cast<std::uint32_t>(end - r0) >> 3));
    }
  }
  return out;
}

}  // namespace loopscan
