#include "loopscan/core/database/scan_context_keys.hpp"

#include <algorithm>

#include "loopscan/core/database/key_scan.hpp"
#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#endif

namespace loopscan {
namespace {

// |d|^2 < 2^32 fits a uint32; the sum a uint64. The oracle of the AVX2 kernel and its tail.
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
#if LOOPSCAN_HAVE_AVX2_CLONES
// 16 dimensions a step: |a - b| as uint16 (max - min), its square split into 16-bit halves by
// mullo / mulhi and re-joined as uint32 lanes, summed in uint64 lanes: exact, as the scalar.
LOOPSCAN_AVX2 std::uint64_t key_distance_avx2(const std::uint16_t* a, const std::uint16_t* b,
                                              std::size_t n) {
  const __m256i low32 = _mm256_set1_epi64x(0xffffffff);
  __m256i acc = _mm256_setzero_si256();
  std::size_t t = 0;
  for (; t + 16 <= n; t += 16) {
    const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + t));
    const __m256i y = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + t));
    const __m256i d = _mm256_sub_epi16(_mm256_max_epu16(x, y), _mm256_min_epu16(x, y));
    const __m256i lo = _mm256_mullo_epi16(d, d), hi = _mm256_mulhi_epu16(d, d);
    for (const __m256i sq : {_mm256_unpacklo_epi16(lo, hi), _mm256_unpackhi_epi16(lo, hi)}) {
      acc = _mm256_add_epi64(acc, _mm256_and_si256(sq, low32));
      acc = _mm256_add_epi64(acc, _mm256_srli_epi64(sq, 32));
    }
  }
  alignas(32) std::uint64_t lanes[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), acc);
  return lanes[0] + lanes[1] + lanes[2] + lanes[3] + key_distance_impl(a + t, b + t, n - t);
}
#endif

int coarse_group(int rings) { return (2 * rings + KeyScan::kMaxDims - 1) / KeyScan::kMaxDims; }

}  // namespace

std::uint64_t spectral_key_distance(const std::uint16_t* a, const std::uint16_t* b, std::size_t n) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const auto kernel = simd::has_avx2() ? key_distance_avx2 : key_distance_base;
  return kernel(a, b, n);
#else
  return key_distance_base(a, b, n);
#endif
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
