// A translation unit apart from scan_context_spectra.cpp: built with -ffp-contract=off.
#include "loopscan/core/matching/scaled_accumulate.hpp"

#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#endif

namespace loopscan {
namespace {

void accumulate_base(float* out, const float* row, float v, int n) {
  for (int k = 0; k < n; ++k) out[k] += v * row[k];
}

#if LOOPSCAN_HAVE_AVX2_CLONES
LOOPSCAN_AVX2 void accumulate_avx2(float* out, const float* row, float v, int n) {
  const __m256 s = _mm256_set1_ps(v);
  int k = 0;
  for (; k + 8 <= n; k += 8) {
    const __m256 p = _mm256_mul_ps(s, _mm256_loadu_ps(row + k));
    _mm256_storeu_ps(out + k, _mm256_add_ps(_mm256_loadu_ps(out + k), p));
  }
  for (; k < n; ++k) out[k] += v * row[k];
}

LOOPSCAN_AVX512 void accumulate_avx512(float* out, const float* row, float v, int n) {
  const __m512 s = _mm512_set1_ps(v);
  for (int k = 0; k < n; k += 16) {
    const int left = n - k;
    const __mmask16 m = static_cast<__mmask16>(simd::first_lanes(left));
    const __m512 p = _mm512_mul_ps(s, _mm512_maskz_loadu_ps(m, row + k));
    _mm512_mask_storeu_ps(out + k, m, _mm512_add_ps(_mm512_maskz_loadu_ps(m, out + k), p));
  }
}
#endif

}  // namespace

void scaled_accumulate(float* out, const float* row, float v, int n) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const auto kernel = simd::widest(accumulate_avx512, accumulate_avx2, accumulate_base);
#else
  static const auto kernel = accumulate_base;
#endif
  kernel(out, row, v, n);
}

}  // namespace loopscan
