#include "loopscan/core/database/compact_spectra.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#endif

namespace loopscan {

void compress_spectra(const CompactSpectraShape& shape, const float* packed, float* out) {
  const int S = shape.sectors;
  std::memset(out, 0, shape.floats() * sizeof(float));
  auto* bytes = reinterpret_cast<std::int8_t*>(out + shape.rows);
  for (int r = 0; r < shape.rows; ++r) {
    const float* x = packed + static_cast<std::size_t>(r) * S;
    float peak = 0;
    for (int k = 0; k < S; ++k) peak = std::max(peak, std::abs(x[k]));
    const float scale = peak / 127.f;
    out[r] = scale;
    if (scale == 0) continue;  // an empty ring (or half) stays exactly zero
    const float inverse = 1.f / scale;
    std::int8_t* q = bytes + static_cast<std::size_t>(r) * S;
    for (int k = 0; k < S; ++k) {
      q[k] = static_cast<std::int8_t>(std::clamp(std::lrint(x[k] * inverse), -127L, 127L));
    }
  }
}

namespace {

// The same loop compiled for AVX2 (8 bytes widened per instruction) and for the baseline.
LOOPSCAN_INLINE void expand_rows(const CompactSpectraShape& shape, const float* compact,
                                 float* out) {
  const int S = shape.sectors;
  const auto* bytes = reinterpret_cast<const std::int8_t*>(compact + shape.rows);
  for (int r = 0; r < shape.rows; ++r) {
    const float scale = compact[r];
    const std::int8_t* __restrict q = bytes + static_cast<std::size_t>(r) * S;
    float* __restrict x = out + static_cast<std::size_t>(r) * S;
    for (int k = 0; k < S; ++k) x[k] = scale * static_cast<float>(q[k]);
  }
}

void expand_base(const CompactSpectraShape& shape, const float* compact, float* out) {
  expand_rows(shape, compact, out);
}
LOOPSCAN_AVX2 void expand_avx2(const CompactSpectraShape& shape, const float* compact, float* out) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  const int S = shape.sectors;
  const auto* bytes = reinterpret_cast<const std::int8_t*>(compact + shape.rows);
  for (int r = 0; r < shape.rows; ++r) {
    const __m256 scale = _mm256_set1_ps(compact[r]);
    const std::int8_t* q = bytes + static_cast<std::size_t>(r) * S;
    float* x = out + static_cast<std::size_t>(r) * S;
    int k = 0;
    for (; k + 8 <= S; k += 8) {
      const __m128i eight = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(q + k));
      _mm256_storeu_ps(x + k,
                       _mm256_mul_ps(scale, _mm256_cvtepi32_ps(_mm256_cvtepi8_epi32(eight))));
    }
    for (; k < S; ++k) x[k] = compact[r] * static_cast<float>(q[k]);
  }
#else
  expand_rows(shape, compact, out);
#endif
}

#if LOOPSCAN_HAVE_AVX2_CLONES
// 16 bytes a step, the ring's tail masked; each value is the same product as in expand_rows.
LOOPSCAN_AVX512 void expand_avx512(const CompactSpectraShape& shape, const float* compact,
                                   float* out) {
  const int S = shape.sectors;
  const auto* bytes = reinterpret_cast<const std::int8_t*>(compact + shape.rows);
  for (int r = 0; r < shape.rows; ++r) {
    const __m512 scale = _mm512_set1_ps(compact[r]);
    const std::int8_t* q = bytes + static_cast<std::size_t>(r) * S;
    float* x = out + static_cast<std::size_t>(r) * S;
    for (int k = 0; k < S; k += 16) {
      const int left = S - k;
      const __mmask16 m = static_cast<__mmask16>(simd::first_lanes(left));
      __m128i sixteen;
      if (left >= 16) {
        sixteen = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q + k));
      } else {  // no read past the record (byte-masked loads need AVX512BW)
        alignas(16) std::int8_t tail[16] = {};
        std::memcpy(tail, q + k, static_cast<std::size_t>(left));
        sixteen = _mm_load_si128(reinterpret_cast<const __m128i*>(tail));
      }
      _mm512_mask_storeu_ps(x + k, m,
                            _mm512_mul_ps(scale, _mm512_maskz_cvtepi32_ps(
                                                     m, _mm512_maskz_cvtepi8_epi32(m, sixteen))));
    }
  }
}
#endif

}  // namespace

void expand_spectra(const CompactSpectraShape& shape, const float* compact, float* out) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const auto kernel = simd::widest(expand_avx512, expand_avx2, expand_base);
#else
  static const auto kernel = expand_base;
#endif
  kernel(shape, compact, out);
}

}  // namespace loopscan
