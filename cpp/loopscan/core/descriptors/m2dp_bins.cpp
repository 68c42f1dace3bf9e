// A translation unit apart from m2dp.cpp: built with -fno-math-errno -ffp-contract=off.
#include "loopscan/core/descriptors/m2dp_bins.hpp"

#include <cmath>

#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#endif

namespace loopscan {
namespace {

// Lane-wise select; comparisons of GCC vectors give -1 (true) / 0 masks.
template <typename Vec, typename VecI>
LOOPSCAN_INLINE Vec select(VecI mask, Vec a, Vec b) {
  return (Vec)((mask & (VecI)a) | (~mask & (VecI)b));  // vector casts reinterpret the bits
}

}  // namespace

M2dpBinner::M2dpBinner(int sectors, int rings, double max_radius_m)
    : sectors_(sectors), rings_(rings), max_radius_(max_radius_m) {
  while ((1 << shift_) < sectors) ++shift_;
  for (int j = 1; j < sectors / 4; ++j) {
    const double a = j * 2.0 * M_PI / sectors;
    ray_cos_.push_back(static_cast<float>(std::cos(a)));
    ray_sin_.push_back(static_cast<float>(std::sin(a)));
  }
}

namespace {

// The kernel, unrolled for a fixed number of boundary rays per quadrant.
// count_row == nullptr: the packed path, `gray_row` is then a long long row (see
// M2dpBinner::accumulate_packed).
template <int kRays, int W>
LOOPSCAN_INLINE void bin_kernel(const PlanarCloud& c, const float (&axes)[6], float ring_inv,
                                int rings, int sector_shift, const float* ray_cos,
                                const float* ray_sin, const float* gray, double* count_row,
                                double* gray_row) {
  long long* packed_row = reinterpret_cast<long long*>(gray_row);
  using Vec = typename simd::Vec<float, W>::type;
  using VecI = typename simd::Vec<int, W>::type;
  constexpr int kLanes = simd::Vec<float, W>::kLanes;
  constexpr int per_quadrant = kRays + 1;
  for (std::size_t i = 0; i < c.x.size(); i += kLanes) {
    const Vec px = simd::load<Vec>(&c.x[i]), py = simd::load<Vec>(&c.y[i]),
              pz = simd::load<Vec>(&c.z[i]);
    // The AVX2+FMA clone fuses explicitly where GCC -O3 used to contract (this file is built
    // with -ffp-contract=off, so no other build type or level fuses differently); the SSE2
    // one has no FMA. packed_avx512 repeats the fused form.
    Vec xp, yp, r2;
    if constexpr (W == 32) {
      for (int l = 0; l < kLanes; ++l) {
        xp[l] = __builtin_fmaf(axes[2], pz[l], __builtin_fmaf(axes[0], px[l], axes[1] * py[l]));
        yp[l] = __builtin_fmaf(axes[5], pz[l], __builtin_fmaf(axes[3], px[l], axes[4] * py[l]));
        r2[l] = __builtin_fmaf(xp[l], xp[l], yp[l] * yp[l]);
      }
    } else {
      xp = axes[0] * px + axes[1] * py + axes[2] * pz;
      yp = axes[3] * px + axes[4] * py + axes[5] * pz;
      r2 = xp * xp + yp * yp;
    }
    Vec rf;
    for (int l = 0; l < kLanes; ++l) rf[l] = __builtin_sqrtf(r2[l]);  // becomes one sqrtps
    rf *= ring_inv;  // may exceed int range: clamped before the conversion
    const VecI ring = __builtin_convertvector(rf < float(rings) ? rf : Vec{} + float(rings), VecI);
    // atan2(y, x) + pi is the angle of (-x, -y): fold it into [0, pi) then [0, pi/2).
    Vec u = -xp, v = -yp;
    const VecI lower = (v < 0) | ((v == 0) & (u < 0));
    u = select(lower, -u, u);
    v = select(lower, -v, v);
    const VecI second = (u <= 0) & (v > 0);
    const Vec u2 = select(second, v, u), v2 = select(second, -u, v);
    VecI sector = ((lower & 2) + (second & 1)) * per_quadrant;
    for (int j = 0; j < kRays; ++j) sector -= (v2 * ray_cos[j] >= u2 * ray_sin[j]);  // -1 masks
    const VecI valid = ring < rings;
    const VecI out = (valid & ((ring << sector_shift) + sector)) | ~valid;  // -1 beyond range
    // Scatter straight from the register: no round trip through a bin array.
    if (!count_row) {
      // Branch-free: beyond range goes to the spare slot `bins`; odd lanes add into a second
      // copy of the row (at packed_row + bins + 1), so runs of one bin make two shorter chains.
      const int bins = rings << sector_shift;
      const VecI slot = (valid & ((ring << sector_shift) + sector)) | (~valid & bins);
      for (int l = 0; l < kLanes; ++l)
        packed_row[slot[l] + (l & 1) * (bins + 1)] += c.packed[i + l];
      continue;
    }
    for (int l = 0; l < kLanes; ++l) {
      const int b = out[l];
      if (b < 0) continue;
      count_row[b] += 1.0;
      gray_row[b] += gray[i + l];
    }
  }
}

template <int W>
LOOPSCAN_INLINE void dispatch_rays(std::size_t rays, const PlanarCloud& c, const float (&axes)[6],
                                   float ring_inv, int rings, int shift, const float* rc,
                                   const float* rs, const float* g, double* cr, double* gr) {
  switch (rays) {
    case 1:
      return bin_kernel<1, W>(c, axes, ring_inv, rings, shift, rc, rs, g, cr, gr);
    case 3:
      return bin_kernel<3, W>(c, axes, ring_inv, rings, shift, rc, rs, g, cr, gr);
    case 7:
      return bin_kernel<7, W>(c, axes, ring_inv, rings, shift, rc, rs, g, cr, gr);
    default:
      return bin_kernel<0, W>(c, axes, ring_inv, rings, shift, rc, rs, g, cr, gr);
  }
}

void kernel_base(std::size_t rays, const PlanarCloud& c, const float (&axes)[6], float ring_inv,
                 int rings, int shift, const float* rc, const float* rs, const float* g, double* cr,
                 double* gr) {
  dispatch_rays<16>(rays, c, axes, ring_inv, rings, shift, rc, rs, g, cr, gr);
}

LOOPSCAN_AVX2 void kernel_avx2(std::size_t rays, const PlanarCloud& c, const float (&axes)[6],
                               float ring_inv, int rings, int shift, const float* rc,
                               const float* rs, const float* g, double* cr, double* gr) {
  dispatch_rays<32>(rays, c, axes, ring_inv, rings, shift, rc, rs, g, cr, gr);
}

#if LOOPSCAN_HAVE_AVX2_CLONES
// The packed path with AVX-512 intrinsics, 16 points at a time (GCC's 64-byte vector code for
// bin_kernel turns the mask logic into scalar code). Every lane computes what bin_kernel's
// AVX2 clone computes, operation for operation (the same explicit multiply-adds), so the bins
// are the same; M2dpOracle checks it on points placed on the bin boundaries. The slots of all
// points first, then the adds in a scalar loop of their own (integer sums: the order does not
// matter): reading 16 slots back right after their 64-byte store, in the same loop, ran 40 %
// slower (5.6 against 4.0 us a plane on k06's scans; store-to-load forwarding, presumably).
// Aligned to 64 bytes: the placement of that loop moved the describe by ~8 % between builds.
template <int kRays>
LOOPSCAN_AVX512 __attribute__((aligned(64))) void packed_avx512(
    const PlanarCloud& c, const float (&axes)[6], float ring_inv, int rings, int shift,
    const float* ray_cos, const float* ray_sin, long long* packed_row) {
  constexpr int kPerQuadrant = kRays + 1;
  constexpr __mmask16 kAll = 0xffff;  // maskz forms: GCC 12 warns about the plain ones' undefined
  const __m512 zero = _mm512_setzero_ps(), sign = _mm512_set1_ps(-0.f);
  const __m512 a0 = _mm512_set1_ps(axes[0]), a1 = _mm512_set1_ps(axes[1]);
  const __m512 a2 = _mm512_set1_ps(axes[2]), a3 = _mm512_set1_ps(axes[3]);
  const __m512 a4 = _mm512_set1_ps(axes[4]), a5 = _mm512_set1_ps(axes[5]);
  const __m512 inv = _mm512_set1_ps(ring_inv), rings_f = _mm512_set1_ps(float(rings));
  const __m512i rings_i = _mm512_set1_epi32(rings), one = _mm512_set1_epi32(1);
  const int bins = rings << shift;
  const __m512i spare = _mm512_set1_epi32(bins);
  // Odd lanes add into the second copy of the row, as bin_kernel does.
  const __m512i copy =
      _mm512_mullo_epi32(_mm512_set_epi32(1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0),
                         _mm512_set1_epi32(bins + 1));
  __m512 rc[kRays > 0 ? kRays : 1], rs[kRays > 0 ? kRays : 1];
  for (int j = 0; j < kRays; ++j) {
    rc[j] = _mm512_set1_ps(ray_cos[j]);
    rs[j] = _mm512_set1_ps(ray_sin[j]);
  }
  thread_local std::vector<int> slot;
  slot.resize(c.x.size());
  int* at_all = slot.data();
  const long long* packed = c.packed.data();
  const std::size_t n = c.x.size();
  for (std::size_t i = 0; i < n; i += 16) {
    const __m512 px = _mm512_loadu_ps(&c.x[i]), py = _mm512_loadu_ps(&c.y[i]),
                 pz = _mm512_loadu_ps(&c.z[i]);
    // bin_kernel's AVX2 clone: fma(a, b, c * d) for a * b + c * d.
    const __m512 xp = _mm512_fmadd_ps(a2, pz, _mm512_fmadd_ps(a0, px, _mm512_mul_ps(a1, py)));
    const __m512 yp = _mm512_fmadd_ps(a5, pz, _mm512_fmadd_ps(a3, px, _mm512_mul_ps(a4, py)));
    const __m512 r2 = _mm512_fmadd_ps(xp, xp, _mm512_mul_ps(yp, yp));
    const __m512 rf = _mm512_mul_ps(_mm512_maskz_sqrt_ps(kAll, r2), inv);
    const __mmask16 below = _mm512_cmp_ps_mask(rf, rings_f, _CMP_LT_OQ);
    const __m512i ring = _mm512_maskz_cvttps_epi32(kAll, _mm512_mask_blend_ps(below, rings_f, rf));
    __m512 u = _mm512_xor_ps(xp, sign), v = _mm512_xor_ps(yp, sign);
    const __mmask16 lower =
        _mm512_cmp_ps_mask(v, zero, _CMP_LT_OQ) |
        (_mm512_cmp_ps_mask(v, zero, _CMP_EQ_OQ) & _mm512_cmp_ps_mask(u, zero, _CMP_LT_OQ));
    u = _mm512_mask_xor_ps(u, lower, u, sign);
    v = _mm512_mask_xor_ps(v, lower, v, sign);
    const __mmask16 second =
        _mm512_cmp_ps_mask(u, zero, _CMP_LE_OQ) & _mm512_cmp_ps_mask(v, zero, _CMP_GT_OQ);
    const __m512 u2 = _mm512_mask_blend_ps(second, u, v);
    const __m512 v2 = _mm512_mask_blend_ps(second, v, _mm512_xor_ps(u, sign));
    __m512i sector = _mm512_maskz_mov_epi32(lower, _mm512_set1_epi32(2 * kPerQuadrant));
    sector = _mm512_mask_add_epi32(sector, second, sector, _mm512_set1_epi32(kPerQuadrant));
    for (int j = 0; j < kRays; ++j) {
      const __mmask16 past =
          _mm512_cmp_ps_mask(_mm512_mul_ps(v2, rc[j]), _mm512_mul_ps(u2, rs[j]), _CMP_GE_OQ);
      sector = _mm512_mask_add_epi32(sector, past, sector, one);
    }
    const __mmask16 valid = _mm512_cmplt_epi32_mask(ring, rings_i);
    const __m512i bin =
        _mm512_add_epi32(_mm512_maskz_sllv_epi32(kAll, ring, _mm512_set1_epi32(shift)), sector);
    _mm512_storeu_si512(at_all + i,
                        _mm512_add_epi32(_mm512_mask_blend_epi32(valid, spare, bin), copy));
  }
  for (std::size_t i = 0; i < n; i += 4) {
    packed_row[at_all[i]] += packed[i];
    packed_row[at_all[i + 1]] += packed[i + 1];
    packed_row[at_all[i + 2]] += packed[i + 2];
    packed_row[at_all[i + 3]] += packed[i + 3];
  }
}
#endif

}  // namespace

void M2dpBinner::accumulate(const PlanarCloud& c, const Eigen::Vector3d& xa,
                            const Eigen::Vector3d& ya, double* count_row, double* gray_row) const {
  const float axes[6] = {float(xa(0)), float(xa(1)), float(xa(2)),
                         float(ya(0)), float(ya(1)), float(ya(2))};
  const float ring_inv = static_cast<float>(rings_ / max_radius_);
#if LOOPSCAN_HAVE_AVX2_CLONES
  if (!count_row && simd::has_avx512()) {
    auto* row = reinterpret_cast<long long*>(gray_row);
    const float *rc = ray_cos_.data(), *rs = ray_sin_.data();
    switch (ray_cos_.size()) {
      case 1:
        return packed_avx512<1>(c, axes, ring_inv, rings_, shift_, rc, rs, row);
      case 3:
        return packed_avx512<3>(c, axes, ring_inv, rings_, shift_, rc, rs, row);
      case 7:
        return packed_avx512<7>(c, axes, ring_inv, rings_, shift_, rc, rs, row);
      default:
        return packed_avx512<0>(c, axes, ring_inv, rings_, shift_, rc, rs, row);
    }
  }
#endif
  auto* kernel = simd::has_avx2() ? kernel_avx2 : kernel_base;
  kernel(ray_cos_.size(), c, axes, ring_inv, rings_, shift_, ray_cos_.data(), ray_sin_.data(),
         c.gray.data(), count_row, gray_row);
}

void M2dpBinner::accumulate_packed(const PlanarCloud& c, const Eigen::Vector3d& xa,
                                   const Eigen::Vector3d& ya, long long* packed_row,
                                   std::size_t stride) const {
  const int bins = sectors_ * rings_;
  thread_local std::vector<long long> two_rows;
  two_rows.assign(2 * (bins + 1), 0);
  accumulate(c, xa, ya, nullptr, reinterpret_cast<double*>(two_rows.data()));
  for (int b = 0; b < bins; ++b) packed_row[b * stride] += two_rows[b] + two_rows[bins + 1 + b];
}

bool pack_gray(PlanarCloud& c, std::size_t n) {
  // Every gray value a multiple of g = the float ulp of the smallest non-zero one; all sums
  // exact (below 2^shift g) when n max / g < 2^shift, shift leaving the count its bits above.
  float lo = 0.f, hi = 0.f;
  for (std::size_t i = 0; i < n; ++i) {
    const float v = c.gray[i];
    if (!(v >= 0.f) || v > 1e30f) return false;  // negative, NaN or inf: the plain path
    if (v > 0.f && (lo == 0.f || v < lo)) lo = v;
    hi = std::max(hi, v);
  }
  int shift = 62;
  while (shift > 0 && (std::size_t{1} << (63 - shift)) <= n) --shift;  // count < 2^(63-shift)
  int e = 0;
  if (lo > 0.f) std::frexp(lo, &e);
  if (lo > 0.f && lo < 1.17549435e-38f) return false;  // subnormal: keep it simple
  c.gray_unit = lo > 0.f ? std::ldexp(1.0, e - 24) : 1.0;
  if (static_cast<double>(n) * hi / c.gray_unit >= std::ldexp(1.0, shift)) return false;
  c.count_shift = shift;
  c.packed.resize(c.gray.size());
  for (std::size_t i = 0; i < c.gray.size(); ++i) {
    c.packed[i] = (1LL << shift) + static_cast<long long>(c.gray[i] / c.gray_unit);
  }
  return true;
}

}  // namespace loopscan
