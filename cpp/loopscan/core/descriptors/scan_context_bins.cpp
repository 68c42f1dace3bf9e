// A translation unit apart from scan_context.cpp: built with -fno-math-errno -ffp-contract=off.
#include "loopscan/core/descriptors/scan_context_bins.hpp"

#include <cmath>
#include <cstddef>
#include <limits>

#include "loopscan/core/descriptors/fast_angle.hpp"
#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#endif

namespace loopscan {
namespace {

constexpr int kMaxSectors = 128;
constexpr int kOut = -1, kFix = -2;  // bins: beyond the last ring; for the exact path

// What the bin kernels share.
struct BinArgs {
  const double *x, *z;  // aligned axes 1 and 2, padded to whole vectors (kPad)
  std::size_t n_vec;
  const Eigen::Vector2d* centres;
  int n_centres, rings, sectors, last;  // last: boundaries tan[1..last] below 45 degrees
  double ring_inv;
  double q1, q2, offset;  // q1 = Q - 1, q2 = 2Q - 1 (Q sectors a quadrant), offset bins
  const double* tan;
  const AngleBinner* binner;
  int* bins;  // n_centres x n_vec: bin, kOut or kFix
};

constexpr int kPad = 16;  // the widest kernel's lanes

// a1, a2 exactly as the scalar loop (-ffp-contract=off for this file); the ring and the sector
// then in single precision with margins far above its rounding (~1e-7): lanes within 1e-5 (in
// tan) of a sector boundary or 1e-4 (in rings) of a ring boundary get kFix and their bin from
// the doubles (AngleBinner, exact); every other lane's float decisions are the double ones.
template <int W, int kLast>
LOOPSCAN_INLINE void bin_points(const BinArgs& a) {
  using V = typename simd::Vec<double, W>::type;
  using F = typename simd::Vec<float, W / 2>::type;
  using VI = typename simd::Vec<int, W / 2>::type;
  constexpr int kV = simd::Vec<double, W>::kLanes;
  const int last = kLast > 0 ? kLast : a.last;
  float lo[kMaxSectors], hi[kMaxSectors];
  for (int j = 0; j <= last; ++j) {
    lo[j] = static_cast<float>(a.tan[j] - 1e-5);
    hi[j] = static_cast<float>(a.tan[j] + 1e-5);
  }
  const F zero{}, one = zero + 1.f;
  const float rings = static_cast<float>(a.rings), ring_inv = static_cast<float>(a.ring_inv);
  const float q1 = static_cast<float>(a.q1), q2 = static_cast<float>(a.q2);
  const float offset = static_cast<float>(a.offset);
  for (std::size_t i = 0; i < a.n_vec; i += kV) {
    const V x = simd::load<V>(a.x + i), z = simd::load<V>(a.z + i);
    for (int c = 0; c < a.n_centres; ++c) {
      const V a1 = x - a.centres[c].x(), a2 = z - a.centres[c].y();
      const F d2 = __builtin_convertvector(a1 * a1 + a2 * a2, F);
      F r;
      for (int l = 0; l < kV; ++l) r[l] = __builtin_sqrtf(d2[l]);
      r *= ring_inv;
      const F in = r < rings + 1.f ? r : zero;
      const F ring = __builtin_convertvector(__builtin_convertvector(in, VI), F);
      const F frac = r - ring;
      const F a1f = __builtin_convertvector(a1, F), a2f = __builtin_convertvector(a2, F);
      const F ax = a1f < 0 ? -a1f : a1f, ay = a2f < 0 ? -a2f : a2f;
      const F mx = ay > ax ? ay : ax, mn = ay > ax ? ax : ay;
      F k_lo = mn > lo[0] * mx ? one : zero, k = mn >= hi[0] * mx ? one : zero;
      for (int j = 1; j <= last; ++j) {
        k_lo += mn > lo[j] * mx ? one : zero;
        k += mn >= hi[j] * mx ? one : zero;
      }
      k -= 1.f;
      const F kb = ay > ax ? q1 - k : k;
      const F upper = a1f >= 0 ? kb : q2 - kb;
      const F sector = (a2f >= 0 ? upper : -1.f - upper) + offset;
      // Flags add up (compilers scalarise mask logic): k_lo - k is 1 off the boundaries and
      // 2 or more next to one; on an axis (k_lo - k may be anything) or next to a ring
      // boundary, 100 each.
      const F big = zero + 100.f;
      // Coordinates below 1e-30 (subnormal floats have too few bits) take the exact path too.
      const F flag = (k_lo - k) + (mn > 0 ? zero : big) + (mx < 1e-30f ? big : zero) +
                     (frac < 1e-4f ? big : zero) + (frac > 1.f - 1e-4f ? big : zero);
      const F fix_or_bin = flag > 1.5f ? zero + kFix : sector * rings + ring;
      const F bin =
          r < rings - 1e-4f ? fix_or_bin : (r > rings + 1e-4f ? zero + kOut : zero + kFix);
      simd::store(a.bins + c * a.n_vec + i, __builtin_convertvector(bin, VI));
    }
  }
}

template <int W>
LOOPSCAN_INLINE void bin_dispatch(const BinArgs& a) {
  if (a.last == 7) return bin_points<W, 7>(a);  // 60 sectors
  bin_points<W, 0>(a);
}

void bins_base(const BinArgs& a) { bin_dispatch<16>(a); }
LOOPSCAN_AVX2 void bins_avx2(const BinArgs& a) { bin_dispatch<32>(a); }

#if LOOPSCAN_HAVE_AVX2_CLONES
// The portable kernel's decisions (bin_points) with 16 float lanes and mask
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

// AVX-512 intrinsics kernel, 16 points at a time (call only when simd::has_avx512()): the same
// bins as the portable kernels wherever they are not kFix (the lanes each sends to the exact
// path may differ; the exact path gives every lane its definition's bin).
void bins_avx512_intrinsics(const BinArgs& a) {
  if (a.last == 7) return kernel<7>(a);  // 60 sectors
  kernel<0>(a);
}
#endif

using Pair = simd::Vec<double, 16>::type;

// (-low, high) and (gray sum, count): one max and one add a point.
struct Cell {
  Pair neg_low_high, gray_count;
};

// Every centre's bins in point order (the gray sums' order), with bin_aligned's updates: max
// keeps its second operand on ties as std::min(low, v) and std::max(high, v) keep theirs; the
// centres' chains of updates are independent, so they overlap.
void accumulate(const BinArgs& a, const double* h, const float* g, std::size_t n, int nb,
                Cell* cells) {
  for (std::size_t i = 0; i < n; ++i) {
    const Pair v{-h[i], h[i]}, add{double(g[i]), 1.0};
    for (int c = 0; c < a.n_centres; ++c) {
      int b = a.bins[c * a.n_vec + i];
      if (b < 0) {
        if (b == kOut) continue;
        // The kernel's doubles, recomputed; the sector from AngleBinner as bin_aligned does.
        const double a1 = a.x[i] - a.centres[c].x(), a2 = a.z[i] - a.centres[c].y();
        const double r = std::sqrt(a1 * a1 + a2 * a2) * a.ring_inv;
        if (!(r < a.rings)) continue;  // beyond the last ring, as bin_aligned drops it
        b = ((*a.binner)(a2, a1) % a.sectors) * a.rings + static_cast<int>(r);
      }
      Cell& e = cells[c * nb + b];
      e.neg_low_high = v > e.neg_low_high ? v : e.neg_low_high;
      e.gray_count += add;
    }
  }
}

// One cell's structure and intensity values (empty cells: 0), scalar.
LOOPSCAN_INLINE void finalise_cell(const Cell& e, bool max_height, double sensor, double mean,
                                   double* structure, double* intensity) {
  const double low = -e.neg_low_high[0], high = e.neg_low_high[1];
  const double gray = e.gray_count[0], count = e.gray_count[1];
  const double s = max_height ? std::max(0.0, high + sensor) : high - low;
  *structure = count > 0 ? s : 0.0;
  *intensity = count > 0 && gray / count > mean ? 1.0 : 0.0;
}

// Four cells at a time (a 4 x 4 transpose, then selects and one vector division): which cells
// are occupied is as unpredictable as the scene, and a scalar division a cell is slow.
LOOPSCAN_INLINE void finalise_cells(const Cell* cells, int nb, bool max_height, double sensor,
                                    double mean, double* row) {
  using V = simd::Vec<double, 32>::type;
  using M = simd::Vec<long long, 32>::type;
  const V zero{}, one = zero + 1.0;
  int b = 0;
  for (; b + 4 <= nb; b += 4) {
    const V c0 = simd::load<V>(&cells[b]), c1 = simd::load<V>(&cells[b + 1]);
    const V c2 = simd::load<V>(&cells[b + 2]), c3 = simd::load<V>(&cells[b + 3]);
    const V t0 = __builtin_shuffle(c0, c1, M{0, 4, 2, 6}),
            t1 = __builtin_shuffle(c0, c1, M{1, 5, 3, 7});
    const V t2 = __builtin_shuffle(c2, c3, M{0, 4, 2, 6}),
            t3 = __builtin_shuffle(c2, c3, M{1, 5, 3, 7});
    const V low = -__builtin_shuffle(t0, t2, M{0, 1, 4, 5});
    const V gray = __builtin_shuffle(t0, t2, M{2, 3, 6, 7});
    const V high = __builtin_shuffle(t1, t3, M{0, 1, 4, 5});
    const V count = __builtin_shuffle(t1, t3, M{2, 3, 6, 7});
    V s = high - low;
    if (max_height) {
      s = high + sensor;
      s = s > 0.0 ? s : zero;  // std::max(0.0, s): 0 for NaN-free s <= 0
    }
    simd::store(row + b, count > 0 ? s : zero);
    simd::store(row + nb + b, (count > 0) & (gray / count > mean) ? one : zero);
  }
  for (; b < nb; ++b) finalise_cell(cells[b], max_height, sensor, mean, row + b, row + nb + b);
}

void finalise_base(const Cell* c, int nb, bool mh, double s, double mean, double* row) {
  finalise_cells(c, nb, mh, s, mean, row);
}
LOOPSCAN_AVX2 void finalise_avx2(const Cell* c, int nb, bool mh, double s, double mean,
                                 double* row) {
  finalise_cells(c, nb, mh, s, mean, row);
}

}  // namespace

bool scan_context_rows_usable(const ScanContextConfig& c) {
  return c.mode == Mode::Default && c.sectors % 4 == 0 && c.sectors <= kMaxSectors && c.rings > 0 &&
         static_cast<long>(c.rings) * c.sectors < (1L << 30);
}

namespace {

// `frame` null: `points` are aligned and `mean` given; else they are aligned here, as
// align_scan does (axes * (p - centre)), and the gray mean summed in the same pass.
void rows_impl(const Cloud& points, const AlignFrame* frame, const ScanContextConfig& config,
               const std::vector<Eigen::Vector2d>& centres, double mean, Eigen::MatrixXd& out) {
  const Cloud& aligned = points;
  const int rings = config.rings, sectors = config.sectors, nb = rings * sectors;
  const AngleBinner binner(sectors / (2.0 * M_PI), M_PI);
  const std::size_t n = aligned.size(), n_vec = (n + kPad - 1) / kPad * kPad;
  thread_local std::vector<double> x, z, h;
  thread_local std::vector<float> g;
  thread_local std::vector<int> bins;
  x.assign(n_vec, 1e30);  // padding lands beyond the last ring
  z.assign(n_vec, 0.0);
  h.resize(n);
  g.resize(n);
  if (frame) {
    double sum = 0.0;  // cloud_gray_mean's sum, in the same order
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d p = frame->axes * (points[i].p - frame->centre);
      x[i] = p(1);
      z[i] = p(2);
      h[i] = p(0);
      g[i] = points[i].intensity;
      sum += points[i].intensity;
    }
    mean = n > 0 ? sum / static_cast<double>(n) : 0.0;
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = aligned[i].p(1);
      z[i] = aligned[i].p(2);
      h[i] = aligned[i].p(0);
      g[i] = aligned[i].intensity;
    }
  }
  bins.resize(centres.size() * n_vec);
  const std::vector<double>& tan = binner.boundaries();
  BinArgs a{x.data(),
            z.data(),
            n_vec,
            centres.data(),
            static_cast<int>(centres.size()),
            rings,
            sectors,
            static_cast<int>(tan.size()) - 2,
            rings / config.max_radius_m,
            binner.quadrant_bins() - 1.0,
            2.0 * binner.quadrant_bins() - 1.0,
            static_cast<double>(binner.offset_bins()),
            tan.data(),
            &binner,
            bins.data()};
#if LOOPSCAN_HAVE_AVX2_CLONES
  simd::widest(bins_avx512_intrinsics, bins_avx2, bins_base)(a);
#else
  (simd::has_avx2() ? bins_avx2 : bins_base)(a);
#endif

  thread_local std::vector<Cell> cells;
  const double inf = std::numeric_limits<double>::infinity();
  cells.assign(centres.size() * nb, Cell{Pair{-inf, -inf}, Pair{0.0, 0.0}});
  accumulate(a, h.data(), g.data(), n, nb, cells.data());
  thread_local std::vector<double> row;
  row.resize(2 * nb);
  out.resize(static_cast<Eigen::Index>(centres.size()), 2 * nb);
  const double sensor = config.max_height ? config.sensor_height_m : 0.0;
  auto* finalise = simd::has_avx2() ? finalise_avx2 : finalise_base;
  for (std::size_t c = 0; c < centres.size(); ++c) {
    finalise(&cells[c * nb], nb, config.max_height, sensor, mean, row.data());
    out.row(static_cast<Eigen::Index>(c)) =
        Eigen::Map<const Eigen::RowVectorXd>(row.data(), 2 * nb);
  }
}

}  // namespace

void scan_context_rows(const Cloud& aligned, const ScanContextConfig& config,
                       const std::vector<Eigen::Vector2d>& centres, double mean,
                       Eigen::MatrixXd& out) {
  rows_impl(aligned, nullptr, config, centres, mean, out);
}

void scan_context_rows(const Cloud& scan, const AlignFrame& frame, const ScanContextConfig& config,
                       const std::vector<Eigen::Vector2d>& centres, Eigen::MatrixXd& out) {
  rows_impl(scan, &frame, config, centres, 0.0, out);
}

}  // namespace loopscan
