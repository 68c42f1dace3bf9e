#include "loopscan/vo/stereo_match.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <utility>
#include <vector>

#include <immintrin.h>

#include "loopscan/core/simd.hpp"

namespace loopscan::vo {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The best cost of a search and its neighbours; second is the lowest cost more than one
// disparity away from the best (INT_MAX when there is none).
struct Minimum {
  int best = 0, second = 0;
  int c0 = 0, c1 = 0, c2 = 0;  // costs at best - 1, best, best + 1 (when inside)
};

// best = the first index of the lowest cost, as a scan from 0 finds it.
template <typename C>
LOOPSCAN_INLINE Minimum minimum_of(C* c, int n) {
  C low = c[0];
  for (int i = 1; i < n; ++i) low = std::min(low, c[i]);
  int best = 0;
  while (c[best] != low) ++best;
  Minimum m;
  m.best = best;
  m.c1 = c[best];
  m.c0 = best > 0 ? c[best - 1] : 0;
  m.c2 = best + 1 < n ? c[best + 1] : 0;
  // The lowest cost away from the best: the three around it masked for the scan, then restored.
  const int lo = std::max(0, best - 1), hi = std::min(n - 1, best + 1);
  C saved[3];
  for (int i = lo; i <= hi; ++i) saved[i - lo] = std::exchange(c[i], std::numeric_limits<C>::max());
  C second = std::numeric_limits<C>::max();
  for (int i = 0; i < n; ++i) second = std::min(second, c[i]);
  for (int i = lo; i <= hi; ++i) c[i] = saved[i - lo];
  const bool any = n > hi - lo + 1;
  m.second = any ? static_cast<int>(second) : std::numeric_limits<int>::max();
  return m;
}

// A window search with 16-bit costs: for each window row, r = the reference window's pixels
// and o[k] = where column k's match at the first accumulated disparity lies in the other row.
// Leftwards searches read the other row backwards in disparity, so their costs are accumulated
// in reverse disparity order (contiguous pixels) and turned round before the minimum.
struct NarrowSearch {
  const std::uint8_t* const* ref_rows;    // 2h + 1 window rows, at the window's first column
  const std::uint8_t* const* other_rows;  // 2h + 1 rows, at the first accumulated pixel
  int h, n;
  bool leftwards;
};

// The disparities from i on, one at a time, then the minimum in disparity order.
LOOPSCAN_INLINE Minimum finish_narrow(const NarrowSearch& s, std::uint16_t* c, int i) {
  const int side = 2 * s.h + 1;
  for (; i < s.n; ++i) {
    int sum = 0;
    for (int row = 0; row < side; ++row)
      for (int k = 0; k < side; ++k) sum += std::abs(s.ref_rows[row][k] - s.other_rows[row][i + k]);
    c[i] = static_cast<std::uint16_t>(sum);
  }
  if (s.leftwards) std::reverse(c, c + s.n);
  return minimum_of(c, s.n);
}

// 8 disparities at a time (SSE2), summed over the window in 16-bit lanes: pixels widened to 16
// bits, absolute differences and sums exact (the caller keeps the sums within 16 bits), so both
// kernels give the same costs.
Minimum narrow_base(const NarrowSearch& s, std::uint16_t* c) {
  using V8 = simd::Vec<std::uint8_t, 8>::type;
  using S16 = simd::Vec<std::int16_t, 16>::type;
  using V16 = simd::Vec<std::uint16_t, 16>::type;
  const int side = 2 * s.h + 1;
  int i = 0;
  for (; i + 8 <= s.n; i += 8) {
    V16 sum{};
    for (int row = 0; row < side; ++row) {
      const std::uint8_t* r = s.ref_rows[row];
      const std::uint8_t* o = s.other_rows[row] + i;
      for (int k = 0; k < side; ++k) {
        const S16 d = (S16{} + static_cast<std::int16_t>(r[k])) -
                      __builtin_convertvector(simd::load<V8>(o + k), S16);
        sum += reinterpret_cast<V16>(d < 0 ? -d : d);
      }
    }
    simd::store(c + i, sum);
  }
  return finish_narrow(s, c, i);
}

// The same, 16 disparities at a time.
LOOPSCAN_AVX2 Minimum narrow_avx2(const NarrowSearch& s, std::uint16_t* c) {
  const int side = 2 * s.h + 1;
  int i = 0;
  for (; i + 16 <= s.n; i += 16) {
    __m256i sum = _mm256_setzero_si256();
    for (int row = 0; row < side; ++row) {
      const std::uint8_t* r = s.ref_rows[row];
      const std::uint8_t* o = s.other_rows[row] + i;
      for (int k = 0; k < side; ++k) {
        const __m256i b =
            _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(o + k)));
        const __m256i d = _mm256_sub_epi16(_mm256_set1_epi16(r[k]), b);
        sum = _mm256_add_epi16(sum, _mm256_abs_epi16(d));
      }
    }
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(c + i), sum);
  }
  return finish_narrow(s, c, i);
}

using NarrowKernel = Minimum (*)(const NarrowSearch&, std::uint16_t*);
const NarrowKernel narrow_kernel = simd::has_avx2() ? narrow_avx2 : narrow_base;

// Best disparity searching `other` at x + direction * d, d in [d_lo, d_hi] (clipped to the
// image). `direction` is -1 from the left image into the right one, +1 back.
double search(const cv::Mat& ref, const cv::Mat& other, int x, int y, int direction, int d_lo,
              int d_hi, int h, double uniqueness) {
  const int w = ref.cols;
  if (x - h < 0 || x + h >= w || y - h < 0 || y + h >= ref.rows) return kNaN;
  // Keep the matched window inside `other`.
  if (direction < 0) {
    d_hi = std::min(d_hi, x - h);
  } else {
    d_hi = std::min(d_hi, w - 1 - h - x);
  }
  d_lo = std::max(d_lo, 0);
  if (d_hi - d_lo < 2) return kNaN;
  const int n = d_hi - d_lo + 1;
  Minimum m;
  if ((2 * h + 1) * (2 * h + 1) * 255 <= 65535) {  // 16-bit costs fit: half windows up to 7
    thread_local std::vector<const std::uint8_t*> rows;
    thread_local std::vector<std::uint16_t> costs;
    rows.resize(static_cast<std::size_t>(4 * h + 2));
    costs.resize(static_cast<std::size_t>(n));
    for (int dy = -h; dy <= h; ++dy) {
      rows[h + dy] = ref.ptr<std::uint8_t>(y + dy) + x - h;
      // Column k at disparity d sees other[x - h + k + direction * d]; leftwards the first
      // accumulated disparity is d_hi.
      rows[3 * h + 1 + dy] =
          other.ptr<std::uint8_t>(y + dy) + x - h + (direction < 0 ? -d_hi : d_lo);
    }
    m = narrow_kernel({rows.data(), rows.data() + 2 * h + 1, h, n, direction < 0}, costs.data());
  } else {
    // The other row's pixels in disparity order, so the inner loop runs over contiguous d and
    // vectorises: line[i + m] is the pixel window column m sees at disparity d_lo + i (m
    // mirrored when searching leftwards).
    thread_local std::vector<int> costs;
    thread_local std::vector<std::uint8_t> line;
    costs.assign(static_cast<std::size_t>(n), 0);
    line.resize(static_cast<std::size_t>(n + 2 * h));
    for (int dy = -h; dy <= h; ++dy) {
      const std::uint8_t* r = ref.ptr<std::uint8_t>(y + dy) + x - h;
      const std::uint8_t* o = other.ptr<std::uint8_t>(y + dy) + x - h;
      for (int k = 0; k < n + 2 * h; ++k)
        line[k] = direction < 0 ? o[2 * h - d_lo - k] : o[d_lo + k];
      for (int k = 0; k <= 2 * h; ++k) {
        const int a = r[k];
        const std::uint8_t* b = line.data() + (direction < 0 ? 2 * h - k : k);
        int* c = costs.data();
        for (int i = 0; i < n; ++i) c[i] += std::abs(a - static_cast<int>(b[i]));
      }
    }
    m = minimum_of(costs.data(), n);
  }
  if (m.best == 0 || m.best == n - 1) return kNaN;
  if (m.second == 0 || m.c1 >= uniqueness * m.second) return kNaN;
  // Equiangular (V-shaped) sub-pixel fit: SAD grows linearly away from the match, so a
  // parabola would pull estimates towards whole pixels.
  const double c0 = m.c0, c1 = m.c1, c2 = m.c2;
  const double slope = std::max(c0, c2) - c1;
  const double offset = slope > 0 ? 0.5 * (c0 - c2) / slope : 0.0;
  return d_lo + m.best + std::clamp(offset, -0.5, 0.5);
}

}  // namespace

double match_disparity(const cv::Mat& left, const cv::Mat& right, int x, int y,
                       const StereoSearch& s) {
  CV_Assert(left.type() == CV_8UC1 && right.type() == CV_8UC1 && left.size() == right.size());
  // No disparity is larger than the image is wide: the search range is clamped to it before
  // the conversion (a huge bf / depth ratio would overflow int).
  const double widest = left.cols;
  if (!(s.min_disparity <= s.max_disparity)) return kNaN;  // also NaN bounds
  const int d_lo = static_cast<int>(std::floor(std::clamp(s.min_disparity, 0.0, widest)));
  const int d_hi = static_cast<int>(std::ceil(std::clamp(s.max_disparity, 0.0, widest)));
  const double d = search(left, right, x, y, -1, d_lo, d_hi, s.half_window, s.uniqueness);
  if (!std::isfinite(d) || !s.left_right_check) return d;
  const int xr = static_cast<int>(std::lround(x - d));
  const double back = search(right, left, xr, y, +1, d_lo, d_hi, s.half_window, s.uniqueness);
  return std::isfinite(back) && std::abs(back - d) <= 1.0 ? d : kNaN;
}

}  // namespace loopscan::vo
