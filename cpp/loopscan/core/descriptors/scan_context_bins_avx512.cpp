#include "loopscan/core/descriptors/scan_context_bin_args.hpp"
#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#endif

namespace loopscan::scan_context_detail {

#if LOOPSCAN_HAVE_AVX2_CLONES
namespace {

// The portable kernel's decisions (scan_context_bins.cpp) with 16 float lanes and mask
// registers: GCC's vector code for them at 64 bytes compares 8 lanes at a time and adds 0/1
// floats for every boundary twice. Here the sector counts the boundaries below t = tan of the
// angle to the nearer axis (one division), and only the two around it are checked for the
// margin. Float error on t: a few 1e-7 (t <= 1), far inside the 1e-5 margin, so every lane not
// sent to the exact path gets the double definition's bin.
LOOPSCAN_AVX512 LOOPSCAN_INLINE __m512 to_floats(__m512d lo, __m512d hi) {
  // maskz forms throughout: GCC 12 warns about the plain ones' undefined operand.
  const __m256 l = _mm512_maskz_cvtpd_ps(0xff, lo), h = _mm512_maskz_cvtpd_ps(0xff, hi);
  return _mm512_insertf32x8(_mm512_castps256_ps512(l), h, 1);
}

template <int kLast>  // 0: a.last at run time
LOOPSCAN_AVX512 void kernel(const BinArgs& a) {
  const int last = kLast > 0 ? kLast : a.last;  // at most kMaxSectors / 8
  alignas(64) float tab[32] = {};               // tan[0..last + 1], the last the sentinel 2
  for (int j = 0; j <= last + 1; ++j) tab[j] = static_cast<float>(a.tan[j]);
  const __m512 tab_lo = _mm512_load_ps(tab), tab_hi = _mm512_load_ps(tab + 16);
  __m512 bound[kMaxSectors / 8 + 1];
  for (int j = 1; j <= last; ++j) bound[j] = _mm512_set1_ps(tab[j]);
  constexpr __mmask16 kAll = 0xffff;
  const __m512 zero = _mm512_setzero_ps(), sign = _mm512_set1_ps(-0.f);
  const float rings_f = static_cast<float>(a.rings);
  const __m512 ring_inv = _mm512_set1_ps(static_cast<float>(a.ring_inv));
  const __m512 inside_below = _mm512_set1_ps(rings_f - 1e-4f);
  const __m512 beyond_above = _mm512_set1_ps(rings_f + 1e-4f);
  const __m512 ring_lo = _mm512_set1_ps(1e-4f), ring_hi = _mm512_set1_ps(1.f - 1e-4f);
  const __m512 tan_margin = _mm512_set1_ps(1e-5f), tiny = _mm512_set1_ps(1e-30f);
  const __m512i one = _mm512_set1_epi32(1), q1 = _mm512_set1_epi32(static_cast<int>(a.q1));
  const __m512i q2 = _mm512_set1_epi32(static_cast<int>(a.q2)), ones = _mm512_set1_epi32(-1);
  const __m512i offset = _mm512_set1_epi32(static_cast<int>(a.offset));
  const __m512i rings = _mm512_set1_epi32(a.rings);
  const __m512i fix = _mm512_set1_epi32(kFix), out = _mm512_set1_epi32(kOut);
  for (std::size_t i = 0; i < a.n_vec; i += 16) {
    const __m512d x0 = _mm512_loadu_pd(a.x + i), x1 = _mm512_loadu_pd(a.x + i + 8);
    const __m512d z0 = _mm512_loadu_pd(a.z + i), z1 = _mm512_loadu_pd(a.z + i + 8);
    for (int c = 0; c < a.n_centres; ++c) {
      const __m512d cx = _mm512_set1_pd(a.centres[c].x()), cz = _mm512_set1_pd(a.centres[c].y());
      // a1, a2 and a1 * a1 + a2 * a2 in double, unfused, as the portable kernel.
      const __m512d a1_0 = _mm512_sub_pd(x0, cx), a1_1 = _mm512_sub_pd(x1, cx);
      const __m512d a2_0 = _mm512_sub_pd(z0, cz), a2_1 = _mm512_sub_pd(z1, cz);
      const __m512d d0 = _mm512_add_pd(_mm512_mul_pd(a1_0, a1_0), _mm512_mul_pd(a2_0, a2_0));
      const __m512d d1 = _mm512_add_pd(_mm512_mul_pd(a1_1, a1_1), _mm512_mul_pd(a2_1, a2_1));
      const __m512 r = _mm512_mul_ps(_mm512_maskz_sqrt_ps(kAll, to_floats(d0, d1)), ring_inv);
      const __m512 a1 = to_floats(a1_0, a1_1), a2 = to_floats(a2_0, a2_1);
      // Huge or NaN r converts to INT_MIN: those lanes are kOut or kFix below.
      const __m512i ring = _mm512_maskz_cvttps_epi32(kAll, r);
      const __m512 frac = _mm512_sub_ps(r, _mm512_maskz_cvtepi32_ps(kAll, ring));
      const __m512 ax = _mm512_andnot_ps(sign, a1), ay = _mm512_andnot_ps(sign, a2);
      const __mmask16 steep = _mm512_cmp_ps_mask(ay, ax, _CMP_GT_OQ);
      const __m512 mx = _mm512_maskz_max_ps(kAll, ay, ax),
                   mn = _mm512_maskz_min_ps(kAll, ax, ay);  // the selects
      const __m512 t = _mm512_div_ps(mn, mx);
      __m512i k = _mm512_setzero_si512();
      for (int j = 1; j <= last; ++j) {
        k = _mm512_mask_add_epi32(k, _mm512_cmp_ps_mask(t, bound[j], _CMP_GE_OQ), k, one);
      }
      const __m512 below = _mm512_permutex2var_ps(tab_lo, k, tab_hi);
      const __m512 above = _mm512_permutex2var_ps(tab_lo, _mm512_add_epi32(k, one), tab_hi);
      // Next to a boundary, on an axis (or NaN), subnormal-small, next to a ring: exact path.
      const __mmask16 flag = _mm512_cmp_ps_mask(_mm512_sub_ps(t, below), tan_margin, _CMP_LT_OQ) |
                             _mm512_cmp_ps_mask(_mm512_sub_ps(above, t), tan_margin, _CMP_LT_OQ) |
                             _mm512_cmp_ps_mask(mn, zero, _CMP_NGT_UQ) |
                             _mm512_cmp_ps_mask(mx, tiny, _CMP_LT_OQ) |
                             _mm512_cmp_ps_mask(frac, ring_lo, _CMP_LT_OQ) |
                             _mm512_cmp_ps_mask(frac, ring_hi, _CMP_GT_OQ);
      // AngleBinner's symmetries: steep folds k to Q - 1 - k, x < 0 to 2Q - 1 - kb, y < 0 to
      // ~upper.
      const __m512i kb = _mm512_mask_sub_epi32(k, steep, q1, k);
      const __m512i upper =
          _mm512_mask_sub_epi32(kb, _mm512_cmp_ps_mask(a1, zero, _CMP_LT_OQ), q2, kb);
      const __m512i sector = _mm512_add_epi32(
          _mm512_mask_xor_epi32(upper, _mm512_cmp_ps_mask(a2, zero, _CMP_LT_OQ), upper, ones),
          offset);
      const __m512i bin = _mm512_add_epi32(_mm512_mullo_epi32(sector, rings), ring);
      const __mmask16 inside = _mm512_cmp_ps_mask(r, inside_below, _CMP_LT_OQ);
      const __mmask16 beyond = _mm512_cmp_ps_mask(r, beyond_above, _CMP_GT_OQ);
      __m512i res = _mm512_mask_blend_epi32(beyond, fix, out);
      res = _mm512_mask_blend_epi32(inside, res, _mm512_mask_blend_epi32(flag, bin, fix));
      _mm512_storeu_si512(a.bins + c * a.n_vec + i, res);
    }
  }
}

}  // namespace

void bins_avx512_intrinsics(const BinArgs& a) {
  if (a.last == 7) return kernel<7>(a);  // 60 sectors
  kernel<0>(a);
}
#else
void bins_avx512_intrinsics(const BinArgs&) {}
#endif

}  // namespace loopscan::scan_context_detail
