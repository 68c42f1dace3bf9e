#include "loopscan/sim/texture_noise.hpp"

#include <immintrin.h>

#include "loopscan/core/simd.hpp"

namespace loopscan::sim {
namespace {

double fade(double t) { return t * t * (3.0 - 2.0 * t); }
double lerp(double a, double b, double t) { return a + (b - a) * t; }

// Corner values of recently used lattice cells, per thread (direct-mapped): neighbouring pixels
// mostly fall into the same cells, and a lookup costs far less than four hashes.
struct Cell2 {
  std::uint32_t salt, ix, iy, used;
  double v[4];
};
thread_local Cell2 cells2[256];

// The corner values of a cell not in the cache, out of line: the hit path then needs no saved
// registers and inlines into fbm2.
__attribute__((noinline)) void fill_cell(Cell2& c, std::uint32_t salt, std::uint32_t ix,
                                         std::uint32_t iy) {
  c = Cell2{salt,
            ix,
            iy,
            1,
            {hash_unit(salt, ix, iy), hash_unit(salt, ix + 1, iy), hash_unit(salt, ix, iy + 1),
             hash_unit(salt, ix + 1, iy + 1)}};
}

LOOPSCAN_INLINE const Cell2& cell2(std::uint32_t ix, std::uint32_t iy, std::uint32_t salt) {
  Cell2& c = cells2[(ix * 0x9e3779b1U + iy * 0x85ebca77U + salt * 0xc2b2ae3dU) >> 24];
  if (!c.used || c.salt != salt || c.ix != ix || c.iy != iy) fill_cell(c, salt, ix, iy);
  return c;
}

LOOPSCAN_INLINE double value_noise2_inline(double x, double y, std::uint32_t salt) {
  const double fx = std::floor(x), fy = std::floor(y);
  const std::uint32_t ix = lattice(x), iy = lattice(y);
  const double tx = fade(x - fx), ty = fade(y - fy);
  const Cell2& c = cell2(ix, iy, salt);
  return lerp(lerp(c.v[0], c.v[1], tx), lerp(c.v[2], c.v[3], tx), ty);
}

// The same for 3D cells (eight corners): foliage is shaded with two 3D noises a pixel.
struct Cell3 {
  std::uint32_t salt, ix, iy, iz, used;
  double v[8];  // corner (dx, dy, dz) at dx + 2 dy + 4 dz
};
thread_local Cell3 cells3[256];

__attribute__((noinline)) void fill_cell3(Cell3& c, std::uint32_t salt, std::uint32_t ix,
                                          std::uint32_t iy, std::uint32_t iz) {
  c.salt = salt;
  c.ix = ix;
  c.iy = iy;
  c.iz = iz;
  c.used = 1;
  for (std::uint32_t k = 0; k < 8; ++k)
    c.v[k] = hash_unit(salt, ix + (k & 1), iy + ((k >> 1) & 1), iz + (k >> 2));
}

// The cells of the four lanes' keys (salt, ix, iy, 1) not in their slots, in lane order.
__attribute__((noinline)) void fill_cells(Cell2* const c[4], const std::uint32_t key[4][4]) {
  for (int l = 0; l < 4; ++l)
    if (c[l]->used != 1 || c[l]->salt != key[l][0] || c[l]->ix != key[l][1] ||
        c[l]->iy != key[l][2])
      fill_cell(*c[l], key[l][0], key[l][1], key[l][2]);
}

#if LOOPSCAN_HAVE_AVX2_CLONES
// fbm2(cx, cy, salt, octaves <= 3) and value_noise2(fx, fy, fine_salt) in four AVX2 lanes
// (lanes 0-2: the octaves, unused ones repeating octave 0; lane 3: the fine noise), each lane
// the scalar operations in the scalar order. floor comes from the truncating conversion, so
// every coordinate must lie within +-2^31; it gives +0 where std::floor gives -0 (x = -0),
// which changes nothing (fade(-0) = fade(+0) = +0). Returns false (nothing written) where a
// coordinate is out of range or a cell is not cached: the caller takes the scalar path.
// cache: this thread's cells2 (read by the caller: no thread-local access in here).
LOOPSCAN_AVX2 bool fbm2_and_noise2_avx2(Cell2* cache, double cx, double cy, std::uint32_t salt,
                                        int octaves, double fx, double fy, std::uint32_t fine_salt,
                                        double& fbm, double& fine) {
  const __m256d freq = _mm256_setr_pd(1.0, octaves >= 2 ? 2.0 : 1.0, octaves >= 3 ? 4.0 : 1.0, 1.0);
  const __m256d x = _mm256_mul_pd(_mm256_setr_pd(cx, cx, cx, fx), freq);  // x * 1.0 is x
  const __m256d y = _mm256_mul_pd(_mm256_setr_pd(cy, cy, cy, fy), freq);
  const __m128i s = _mm_setr_epi32(
      static_cast<int>(salt), static_cast<int>(octaves >= 2 ? salt + 7919U : salt),
      static_cast<int>(octaves >= 3 ? salt + 2U * 7919U : salt), static_cast<int>(fine_salt));
  const __m256d lim = _mm256_set1_pd(2147483648.0), nlim = _mm256_set1_pd(-2147483648.0);
  const __m256d in = _mm256_and_pd(
      _mm256_and_pd(_mm256_cmp_pd(x, lim, _CMP_LT_OQ), _mm256_cmp_pd(x, nlim, _CMP_GT_OQ)),
      _mm256_and_pd(_mm256_cmp_pd(y, lim, _CMP_LT_OQ), _mm256_cmp_pd(y, nlim, _CMP_GT_OQ)));
  if (_mm256_movemask_pd(in) != 0xf) return false;
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d tx = _mm256_cvtepi32_pd(_mm256_cvttpd_epi32(x));
  const __m256d ty = _mm256_cvtepi32_pd(_mm256_cvttpd_epi32(y));
  // Truncation rounds negative non-integers up: one less there.
  const __m256d flx = _mm256_sub_pd(tx, _mm256_and_pd(_mm256_cmp_pd(tx, x, _CMP_GT_OQ), one));
  const __m256d fly = _mm256_sub_pd(ty, _mm256_and_pd(_mm256_cmp_pd(ty, y, _CMP_GT_OQ), one));
  const __m128i ix = _mm256_cvttpd_epi32(flx), iy = _mm256_cvttpd_epi32(fly);
  const __m256d ux = _mm256_sub_pd(x, flx), uy = _mm256_sub_pd(y, fly);
  const __m256d three = _mm256_set1_pd(3.0), two = _mm256_set1_pd(2.0);
  const __m256d wx =
      _mm256_mul_pd(_mm256_mul_pd(ux, ux), _mm256_sub_pd(three, _mm256_mul_pd(two, ux)));
  const __m256d wy =
      _mm256_mul_pd(_mm256_mul_pd(uy, uy), _mm256_sub_pd(three, _mm256_mul_pd(two, uy)));
  // Cache slots and keys (salt, ix, iy, used = 1): the cell layout, one compare a lane.
  const __m128i slot = _mm_srli_epi32(
      _mm_add_epi32(_mm_add_epi32(_mm_mullo_epi32(ix, _mm_set1_epi32(0x9e3779b1)),
                                  _mm_mullo_epi32(iy, _mm_set1_epi32(0x85ebca77))),
                    _mm_mullo_epi32(s, _mm_set1_epi32(static_cast<int>(0xc2b2ae3dU)))),
      24);
  const __m128i t0 = _mm_unpacklo_epi32(s, ix), t1 = _mm_unpacklo_epi32(iy, _mm_set1_epi32(1));
  const __m128i t2 = _mm_unpackhi_epi32(s, ix), t3 = _mm_unpackhi_epi32(iy, _mm_set1_epi32(1));
  const __m128i key[4] = {_mm_unpacklo_epi64(t0, t1), _mm_unpackhi_epi64(t0, t1),
                          _mm_unpacklo_epi64(t2, t3), _mm_unpackhi_epi64(t2, t3)};
  Cell2* c[4] = {cache + _mm_cvtsi128_si32(slot), cache + _mm_extract_epi32(slot, 1),
                 cache + _mm_extract_epi32(slot, 2), cache + _mm_extract_epi32(slot, 3)};
  const auto cached = [&] {
    __m128i eq = _mm_set1_epi32(-1);
    for (int l = 0; l < 4; ++l)
      eq = _mm_and_si128(
          eq, _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(c[l])), key[l]));
    return _mm_movemask_epi8(eq) == 0xffff;
  };
  if (!cached()) {
    alignas(16) std::uint32_t k[4][4];
    for (int l = 0; l < 4; ++l) _mm_store_si128(reinterpret_cast<__m128i*>(k[l]), key[l]);
    fill_cells(c, k);
    if (!cached()) return false;  // two lanes share a slot: the scalar path
  }
  // Corners: rows = cells, transposed into corner vectors over the lanes.
  const __m256d r0 = _mm256_loadu_pd(c[0]->v), r1 = _mm256_loadu_pd(c[1]->v);
  const __m256d r2 = _mm256_loadu_pd(c[2]->v), r3 = _mm256_loadu_pd(c[3]->v);
  const __m256d a0 = _mm256_unpacklo_pd(r0, r1), a1 = _mm256_unpackhi_pd(r0, r1);
  const __m256d a2 = _mm256_unpacklo_pd(r2, r3), a3 = _mm256_unpackhi_pd(r2, r3);
  const __m256d v0 = _mm256_permute2f128_pd(a0, a2, 0x20),
                v2 = _mm256_permute2f128_pd(a0, a2, 0x31);
  const __m256d v1 = _mm256_permute2f128_pd(a1, a3, 0x20),
                v3 = _mm256_permute2f128_pd(a1, a3, 0x31);
  const __m256d lo = _mm256_add_pd(v0, _mm256_mul_pd(_mm256_sub_pd(v1, v0), wx));
  const __m256d hi = _mm256_add_pd(v2, _mm256_mul_pd(_mm256_sub_pd(v3, v2), wx));
  double v[4];
  _mm256_storeu_pd(v, _mm256_add_pd(lo, _mm256_mul_pd(_mm256_sub_pd(hi, lo), wy)));
  double sum = 0.0, norm = 0.0, amp = 1.0;  // fbm2's sums, in its order
  for (int o = 0; o < octaves; ++o) {
    sum += amp * v[o];
    norm += amp;
    amp *= 0.5;
  }
  fbm = sum / norm;
  fine = v[3];
  return true;
}
#endif

}  // namespace

LOOPSCAN_SIM_CLONES double value_noise2(double x, double y, std::uint32_t salt) {
  return value_noise2_inline(x, y, salt);
}

LOOPSCAN_SIM_CLONES double value_noise3(double x, double y, double z, std::uint32_t salt) {
  const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const std::uint32_t ix = lattice(x), iy = lattice(y), iz = lattice(z);
  const double tx = fade(x - fx), ty = fade(y - fy), tz = fade(z - fz);
  Cell3& c =
      cells3[(ix * 0x9e3779b1U + iy * 0x85ebca77U + iz * 0x27d4eb2fU + salt * 0xc2b2ae3dU) >> 24];
  if (!c.used || c.salt != salt || c.ix != ix || c.iy != iy || c.iz != iz)
    fill_cell3(c, salt, ix, iy, iz);
  double layer[2];
  for (int k = 0; k < 2; ++k) {
    const double* v = c.v + 4 * k;
    layer[k] = lerp(lerp(v[0], v[1], tx), lerp(v[2], v[3], tx), ty);
  }
  return lerp(layer[0], layer[1], tz);
}

LOOPSCAN_SIM_CLONES double fbm2(double x, double y, std::uint32_t salt, int octaves) {
  double sum = 0.0, norm = 0.0, amp = 1.0, freq = 1.0;
  for (int o = 0; o < octaves; ++o) {
    sum +=
        amp * value_noise2_inline(x * freq, y * freq, salt + static_cast<std::uint32_t>(o) * 7919U);
    norm += amp;
    amp *= 0.5;
    freq *= 2.0;
  }
  return norm > 0.0 ? sum / norm : 0.5;
}

void fbm2_and_noise2(double cx, double cy, std::uint32_t salt, int octaves, double fx, double fy,
                     std::uint32_t fine_salt, double& fbm, double& fine) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  // AVX2 unless LOOPSCAN_NO_AVX2 (the same bits: nothing is contracted into FMAs in this file).
  static const bool avx2 = simd::has_avx2();
  if (avx2 && octaves >= 1 && octaves <= 3 &&
      fbm2_and_noise2_avx2(cells2, cx, cy, salt, octaves, fx, fy, fine_salt, fbm, fine))
    return;
#endif
  fbm = fbm2(cx, cy, salt, octaves);  // fills the cells the lanes missed
  fine = value_noise2(fx, fy, fine_salt);
}

}  // namespace loopscan::sim
