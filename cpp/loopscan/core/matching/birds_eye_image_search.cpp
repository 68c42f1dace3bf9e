// The bird's-eye image search (birds_eye_match.hpp): a place image turned by a yaw and
// correlated with the query image over shifts, first on merged cells, then at full resolution
// around the best coarse peaks.
#include "loopscan/core/matching/birds_eye_match.hpp"

#include "loopscan/core/peak_vertex.hpp"
#include "loopscan/core/simd.hpp"

#include <immintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace loopscan {
namespace {

constexpr int kLanes = 8;  // shifts of a window row summed together

void check_image(const BirdsEyePlace& place, const BirdsEyePlaceConfig& config) {
  const int side = image_side(config);
  if (place.side != side || place.image.size() != std::size_t(side) * std::size_t(side)) {
    throw std::invalid_argument("birds_eye: images of " + std::to_string(side) + " x " +
                                std::to_string(side) + " cells expected");
  }
}

// A square image of floats (a place image, turned, or merged into coarser cells) and its norm.
struct Grid {
  int side = 0;
  std::vector<float> cells;
  double norm = 0;
};

// The place image with f x f cells merged (summed; the last block of a row or column may be
// cut short): the image itself for f = 1. Sums and the norm in integers: exact, and without a
// chain of floating-point additions.
Grid merged_image(const BirdsEyePlace& place, int f) {
  const int n = place.side;
  Grid out;
  out.side = (n + f - 1) / f;
  std::int64_t sq = 0;
  if (f == 1) {
    out.cells.assign(place.image.begin(), place.image.end());
    for (std::uint8_t v : place.image) sq += int(v) * int(v);
    out.norm = std::sqrt(double(sq));
    return out;
  }
  std::vector<int> sums(std::size_t(out.side) * out.side, 0);
  for (int r = 0; r < n; ++r) {
    const std::uint8_t* in = place.image.data() + std::size_t(r) * n;
    int* o = sums.data() + std::size_t(r / f) * out.side;
    for (int c = 0; c < n; ++c) o[c / f] += in[c];
  }
  out.cells.resize(sums.size());
  for (std::size_t i = 0; i < sums.size(); ++i) {
    out.cells[i] = float(sums[i]);
    sq += std::int64_t(sums[i]) * sums[i];
  }
  out.norm = std::sqrt(double(sq));
  return out;
}

// A place image with a border of one zero cell: bilinear samples need no bounds checks.
struct BorderedImage {
  explicit BorderedImage(const Grid& g)
      : n(g.side), side(g.side + 2), cells(std::size_t(side) * side, 0.f) {
    for (int r = 0; r < n; ++r) {
      std::copy(g.cells.begin() + std::ptrdiff_t(r) * n, g.cells.begin() + std::ptrdiff_t(r + 1) * n,
                cells.begin() + std::ptrdiff_t(r + 1) * side + 1);
    }
  }
  int n, side;
  std::vector<float> cells;
};

// The columns [lo, hi] of a row where f0 + d col may lie in (-1, n); empty when lo > hi.
std::pair<int, int> columns_inside(double f0, double d, int n) {
  if (std::abs(d) < 1e-12) return (f0 > -1 && f0 < n) ? std::pair{0, n - 1} : std::pair{0, -1};
  const double a = (-1 - f0) / d, b = (n - f0) / d;
  const double lo = std::max(0.0, std::floor(std::min(a, b))), hi = std::min(n - 1.0, std::ceil(std::max(a, b)));
  return {int(lo), int(hi)};
}

// A place turned into the query's orientation, as its non-zero cells in row-major order.
struct TurnedPlace {
  int side = 0;
  std::vector<int> cells;  // row * side + column
  std::vector<float> values;
  double norm = 0;
};

// One row of a turned image: out[col] for col in [lo, hi] samples the bordered place
// bilinearly at (fc0 + dc col, fr0 + dr col) in fractional cells of the unbordered image, and is
// zero where that lies outside (-1, n) in either axis.
struct TurnedRow {
  const float* cells;  // the bordered image
  int side, n;         // its side and the unbordered side
  double fc0, fr0, dc, dr;
};

void turned_row_base(const TurnedRow& t, int lo, int hi, float* out) {
  const float n = float(t.n);
  for (int col = lo; col <= hi; ++col) {
    const float fc = float(t.fc0 + t.dc * col), fr = float(t.fr0 + t.dr * col);
    if (!(fc > -1.f && fc < n && fr > -1.f && fr < n)) {
      out[col] = 0.f;
      continue;
    }
    const int ci = int(fc + 1.f), ri = int(fr + 1.f);  // floor + 1: the bordered index
    const float wc = fc + 1.f - float(ci), wr = fr + 1.f - float(ri);
    const float* p = t.cells + std::size_t(ri) * t.side + ci;
    const float* q = p + t.side;
    out[col] = (1 - wr) * ((1 - wc) * p[0] + wc * p[1]) + wr * ((1 - wc) * q[0] + wc * q[1]);
  }
}

#if LOOPSCAN_HAVE_AVX2_CLONES
// Eight columns at a time: coordinates in double as the scalar row computes them, the four
// neighbours gathered.
LOOPSCAN_AVX2 void turned_row_avx2(const TurnedRow& t, int lo, int hi, float* out) {
  const __m256d fc0 = _mm256_set1_pd(t.fc0), fr0 = _mm256_set1_pd(t.fr0);
  const __m256d dc = _mm256_set1_pd(t.dc), dr = _mm256_set1_pd(t.dr);
  const __m256 low = _mm256_set1_ps(-1.f), high = _mm256_set1_ps(float(t.n)),
               one = _mm256_set1_ps(1.f);
  const __m256i side = _mm256_set1_epi32(t.side), last = _mm256_set1_epi32(hi);
  const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  for (int col = lo; col <= hi; col += 8) {
    const __m256i cols = _mm256_add_epi32(_mm256_set1_epi32(col), lanes);
    const __m256d c_lo = _mm256_cvtepi32_pd(_mm256_castsi256_si128(cols));
    const __m256d c_hi = _mm256_cvtepi32_pd(_mm256_extracti128_si256(cols, 1));
    const __m256 fc = _mm256_set_m128(_mm256_cvtpd_ps(_mm256_add_pd(fc0, _mm256_mul_pd(dc, c_hi))),
                                      _mm256_cvtpd_ps(_mm256_add_pd(fc0, _mm256_mul_pd(dc, c_lo))));
    const __m256 fr = _mm256_set_m128(_mm256_cvtpd_ps(_mm256_add_pd(fr0, _mm256_mul_pd(dr, c_hi))),
                                      _mm256_cvtpd_ps(_mm256_add_pd(fr0, _mm256_mul_pd(dr, c_lo))));
    __m256 inside =
        _mm256_and_ps(_mm256_cmp_ps(fc, low, _CMP_GT_OQ), _mm256_cmp_ps(fc, high, _CMP_LT_OQ));
    inside = _mm256_and_ps(inside, _mm256_and_ps(_mm256_cmp_ps(fr, low, _CMP_GT_OQ),
                                                 _mm256_cmp_ps(fr, high, _CMP_LT_OQ)));
    inside = _mm256_andnot_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(cols, last)), inside);
    // Outside lanes sample the border's corner (index 0) and are zeroed afterwards.
    const __m256 fc1 = _mm256_and_ps(_mm256_add_ps(fc, one), inside);
    const __m256 fr1 = _mm256_and_ps(_mm256_add_ps(fr, one), inside);
    const __m256i ci = _mm256_cvttps_epi32(fc1), ri = _mm256_cvttps_epi32(fr1);
    const __m256 wc = _mm256_sub_ps(fc1, _mm256_cvtepi32_ps(ci));
    const __m256 wr = _mm256_sub_ps(fr1, _mm256_cvtepi32_ps(ri));
    const __m256i at = _mm256_add_epi32(_mm256_mullo_epi32(ri, side), ci);
    const __m256 p0 = _mm256_i32gather_ps(t.cells, at, 4);
    const __m256 p1 = _mm256_i32gather_ps(t.cells + 1, at, 4);
    const __m256 q0 = _mm256_i32gather_ps(t.cells + t.side, at, 4);
    const __m256 q1 = _mm256_i32gather_ps(t.cells + t.side + 1, at, 4);
    const __m256 uc = _mm256_sub_ps(one, wc), ur = _mm256_sub_ps(one, wr);
    const __m256 top = _mm256_add_ps(_mm256_mul_ps(uc, p0), _mm256_mul_ps(wc, p1));
    const __m256 bottom = _mm256_add_ps(_mm256_mul_ps(uc, q0), _mm256_mul_ps(wc, q1));
    const __m256 v = _mm256_add_ps(_mm256_mul_ps(ur, top), _mm256_mul_ps(wr, bottom));
    _mm256_storeu_ps(out + col, _mm256_and_ps(v, inside));
  }
}
#endif

void turned_row(const TurnedRow& t, int lo, int hi, float* out) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const auto kernel = simd::has_avx2() ? turned_row_avx2 : turned_row_base;
#else
  static const auto kernel = turned_row_base;
#endif
  kernel(t, lo, hi, out);
}

// The place image turned by yaw into the query's orientation: cell p of the result samples the
// place at R(yaw)^T p (bilinear; zero outside). Cells of cell_m from -range_m in x and z.
TurnedPlace turned_image(const BorderedImage& place, double yaw, double cell_m, double range_m) {
  const int n = place.n;
  TurnedPlace out;
  out.side = n;
  out.cells.resize(std::size_t(n) * std::size_t(n));
  out.values.resize(std::size_t(n) * std::size_t(n));
  std::vector<float> row(std::size_t(n) + 8);  // a vector kernel may write 7 columns past n
  std::size_t kept = 0;  // written without a branch: whether a cell is empty is unpredictable
  const double c = std::cos(yaw), s = std::sin(yaw), offset = range_m / cell_m - 0.5;
  double sq = 0;
  for (int r = 0; r < n; ++r) {
    const double z = (r + 0.5) * cell_m - range_m, x0 = 0.5 * cell_m - range_m;
    // R^T (x, z) in fractional cells, R turning x towards z: linear along the row.
    const double fc0 = (c * x0 + s * z) / cell_m + offset, fr0 = (-s * x0 + c * z) / cell_m + offset;
    const auto [c_lo, c_hi] = columns_inside(fc0, c, n);
    const auto [r_lo, r_hi] = columns_inside(fr0, -s, n);
    const int lo = std::max(c_lo, r_lo), hi = std::min(c_hi, r_hi);
    if (lo > hi) continue;
    turned_row({place.cells.data(), place.side, n, fc0, fr0, c, -s}, lo, hi, row.data());
    float row_sq = 0;  // the row's squares in float: the values are bilinear in bytes
    for (int col = lo; col <= hi; ++col) {
      const float v = row[col];
      out.cells[kept] = r * n + col;
      out.values[kept] = v;
      kept += v != 0.f;
      row_sq += v * v;
    }
    sq += row_sq;
  }
  out.cells.resize(kept);
  out.values.resize(kept);
  out.norm = std::sqrt(sq);
  return out;
}

double wrap_angle(double a) {
  a = std::remainder(a, 2 * M_PI);
  return a <= -M_PI ? a + 2 * M_PI : a;
}

// The query image zero-padded by m cells on every side, and by a vector's lanes more on the
// right so that whole vectors of a window's row may be read.
struct PaddedQuery {
  PaddedQuery(const Grid& query, int max_cells)
      : n(query.side), m(max_cells), stride(query.side + 2 * max_cells + kLanes),
        cells(std::size_t(query.side + 2 * max_cells) * stride, 0.f), norm(query.norm) {
    for (int r = 0; r < n; ++r) {
      std::copy(query.cells.begin() + std::ptrdiff_t(r) * n,
                query.cells.begin() + std::ptrdiff_t(r + 1) * n,
                cells.begin() + std::ptrdiff_t(r + m) * stride + m);
    }
  }
  int n, m, stride;
  std::vector<float> cells;
  double norm = 0;
};

// Shifts (dx, dz) of the turned place into the query, dx in [x0, x1] and dz in [z0, z1], all
// within [-m, m].
struct Window {
  int x0, x1, z0, z1;
  int width() const { return x1 - x0 + 1; }
  int height() const { return z1 - z0 + 1; }
};

// Sums over the place's non-zero cells k of values[k] times the Floats query values from
// first + offsets[k] (Floats = 8 or 16): one window row of shifts, the sums in registers.
template <int W, int Floats>
LOOPSCAN_INLINE void row_sums_impl(const float* first, const std::ptrdiff_t* offsets,
                                   const float* values, std::size_t count, float* out) {
  using V = typename simd::Vec<float, W>::type;
  constexpr int L = simd::Vec<float, W>::kLanes, NV = Floats / L;
  V sums[NV] = {};
  for (std::size_t k = 0; k < count; ++k) {
    const float* p = first + offsets[k];
    for (int j = 0; j < NV; ++j) sums[j] += values[k] * simd::load<V>(p + j * L);
  }
  for (int j = 0; j < NV; ++j) simd::store(out + j * L, sums[j]);
}

using RowSums = void (*)(const float*, const std::ptrdiff_t*, const float*, std::size_t, float*);
template <int Floats>
void row_sums_base(const float* f, const std::ptrdiff_t* o, const float* v, std::size_t n,
                   float* out) {
  row_sums_impl<16, Floats>(f, o, v, n, out);
}
#if LOOPSCAN_HAVE_AVX2_CLONES
template <int Floats>
LOOPSCAN_AVX2 void row_sums_avx2(const float* f, const std::ptrdiff_t* o, const float* v,
                                 std::size_t n, float* out) {
  row_sums_impl<32, Floats>(f, o, v, n, out);
}
#endif
// The kernel for Floats sums (a window row's one or two blocks of lanes). A window is at most
// a few blocks wide, so AVX-512 would add nothing over AVX2.
template <int Floats>
RowSums row_sums() {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const RowSums kernel = simd::has_avx2() ? row_sums_avx2<Floats> : row_sums_base<Floats>;
#else
  static const RowSums kernel = row_sums_base<Floats>;
#endif
  return kernel;
}

// A turned place against one padded query: its non-zero cells as offsets into the query, and
// the normalised correlation of every shift within [-m, m]^2 once computed (NaN before), so
// that overlapping windows (a climb's moves, peaks that meet) compute each shift once. A shift's
// value does not depend on the window that computed it: its sum runs over the same cells in
// the same order.
class Correlation {
 public:
  Correlation(const PaddedQuery& query, TurnedPlace turned)
      : query_(query),
        norms_(turned.norm * query.norm),
        side_(2 * query.m + 1),
        values_(std::move(turned.values)),
        table_(std::size_t(side_) * side_, std::numeric_limits<double>::quiet_NaN()) {
    offsets_.reserve(turned.cells.size());
    for (int cell : turned.cells) {
      offsets_.push_back(std::ptrdiff_t(cell / query.n) * query.stride + cell % query.n);
    }
  }

  // The window's correlations, row-major from (x0, z0).
  std::vector<double> window(const Window& w) {
    const int m = query_.m, wx = w.width(), wz = w.height();
    std::vector<double> out(std::size_t(wx) * std::size_t(wz), 0.0);
    if (!(norms_ > 0)) return out;
    alignas(64) float sums[2 * kLanes];
    for (int dz = 0; dz < wz; ++dz) {
      double* row = table_.data() + std::size_t(w.z0 + dz + m) * side_ + std::size_t(m);
      // Query rows from z0 + dz, columns from x, whole blocks of lanes at a time.
      for (int x = w.x0; x <= w.x1;) {
        if (!std::isnan(row[x])) {
          ++x;
          continue;
        }
        const int wide = w.x1 - x + 1 > kLanes ? 2 * kLanes : kLanes;
        const int count = std::min(wide, m - x + 1);
        const float* first =
            query_.cells.data() + std::size_t(w.z0 + dz + m) * query_.stride + std::size_t(x + m);
        (wide > kLanes ? row_sums<2 * kLanes>() : row_sums<kLanes>())(
            first, offsets_.data(), values_.data(), offsets_.size(), sums);
        for (int l = 0; l < count; ++l) row[x + l] = sums[l] / norms_;
        x += count;
      }
      for (int dx = 0; dx < wx; ++dx) out[std::size_t(dz) * wx + dx] = row[w.x0 + dx];
    }
    return out;
  }

 private:
  const PaddedQuery& query_;
  double norms_;
  int side_;
  std::vector<std::ptrdiff_t> offsets_;  // of the place's non-zero cells in the padded query
  std::vector<float> values_;
  std::vector<double> table_;  // shift (x, z) at (z + m) * side + x + m
};

// A peak of a correlation window: the best whole-cell shift, and that shift refined to a
// fraction of a cell where both neighbours along an axis lie in the window.
struct Peak {
  int x = 0, z = 0;
  double dx = 0, dz = 0;
  double score = -1;
};
Peak peak_of(const std::vector<double>& corr, const Window& w) {
  const int wx = w.width(), wz = w.height();
  const auto top = std::max_element(corr.begin(), corr.end());
  const int i = int(top - corr.begin()), row = i / wx, col = i % wx;
  auto at = [&](int r, int c) { return corr[std::size_t(r) * wx + c]; };
  const double fx = (col > 0 && col < wx - 1) ? parabola_vertex(at(row, col - 1), *top, at(row, col + 1)) : 0;
  const double fz = (row > 0 && row < wz - 1) ? parabola_vertex(at(row - 1, col), *top, at(row + 1, col)) : 0;
  return {w.x0 + col, w.z0 + row, w.x0 + col + fx, w.z0 + row + fz, *top};
}

// The local maxima of a square correlation map (ties: the first in row-major order), with the
// yaw they were found at and their shift from the map's centre.
struct CoarsePeak {
  double score;
  int yaw, x, z;
};
void local_maxima(const std::vector<double>& corr, int mc, int yaw, std::vector<CoarsePeak>& out) {
  const int w = 2 * mc + 1;
  auto at = [&](int r, int c) {
    return r < 0 || r >= w || c < 0 || c >= w ? -1.0 : corr[std::size_t(r) * w + c];
  };
  for (int r = 0; r < w; ++r) {
    for (int c = 0; c < w; ++c) {
      const double v = at(r, c);
      bool peak = v > 0;
      for (int dr = -1; dr <= 1 && peak; ++dr) {
        for (int dc = -1; dc <= 1 && peak; ++dc) {
          if (dr == 0 && dc == 0) continue;
          const double o = at(r + dr, c + dc);
          peak = (dr < 0 || (dr == 0 && dc < 0)) ? v > o : v >= o;
        }
      }
      if (peak) out.push_back({v, yaw, c - mc, r - mc});
    }
  }
}

}  // namespace

namespace {

// The weight of each cell of a grid of `side` cells of cell_m from -range_m in the search's pose
// window (by its centre's distance from the keyframe); the last table a thread made is kept,
// as every query of a run asks for the same few.
std::vector<float> pose_weights(int side, double cell_m, double range_m,
                                const BirdsEyeSearchConfig& s) {
  thread_local std::array<double, 5> made_for{};
  thread_local std::vector<float> made;
  const std::array<double, 5> key{double(side), cell_m, range_m, s.pose_window_start_m,
                                  s.pose_window_end_m};
  if (!made.empty() && key == made_for) return made;
  std::vector<float> out(std::size_t(side) * std::size_t(side));
  for (int r = 0; r < side; ++r) {
    for (int col = 0; col < side; ++col) {
      const double d = std::hypot((col + 0.5) * cell_m - range_m, (r + 0.5) * cell_m - range_m);
      out[std::size_t(r) * side + col] =
          float(birds_eye_window_weight(d, s.pose_window_start_m, s.pose_window_end_m));
    }
  }
  made_for = key;
  made = out;
  return out;
}

Grid weighed(Grid g, const std::vector<float>& weights) {
  double sq = 0;
  for (std::size_t i = 0; i < g.cells.size(); ++i) {
    g.cells[i] *= weights[i];
    sq += double(g.cells[i]) * g.cells[i];
  }
  g.norm = std::sqrt(sq);
  return g;
}

// A turned place weighed cell by cell. A weight that depends only on the distance from the
// keyframe turns with the image: weighing after the turn is weighing the place.
TurnedPlace weighed(const TurnedPlace& t, const std::vector<float>& weights) {
  TurnedPlace out;
  out.side = t.side;
  out.cells.reserve(t.cells.size());
  out.values.reserve(t.values.size());
  double sq = 0;
  for (std::size_t k = 0; k < t.cells.size(); ++k) {
    const float v = t.values[k] * weights[std::size_t(t.cells[k])];
    if (v == 0.f) continue;
    out.cells.push_back(t.cells[k]);
    out.values.push_back(v);
    sq += double(v) * v;
  }
  out.norm = std::sqrt(sq);
  return out;
}

// Whether the pose window weighs anything of an image: not when it starts at or beyond the
// image's own window's end (the search then runs on the stored images themselves).
bool pose_window_weighs(const BirdsEyePlaceConfig& c, const BirdsEyeSearchConfig& s) {
  return s.pose_window_start_m < c.taper_end_m;
}

// The query merged f x f, weighed by `weights` (none: as stored).
Grid pose_grid(const BirdsEyePlace& query, int f, const std::vector<float>& weights) {
  Grid g = merged_image(query, f);
  if (weights.empty()) return g;
  return weighed(std::move(g), weights);
}

}  // namespace

struct BirdsEyeImageSearch::Prepared {
  Prepared(const BirdsEyePlace& query, const BirdsEyePlaceConfig& c, const BirdsEyeSearchConfig& s)
      : config(c),
        search(s),
        m(int(std::floor(s.max_shift_m / c.cell_m))),
        f(s.coarse_cells),
        mc((m + f - 1) / f),
        weighs(pose_window_weighs(c, s)),
        weights(weighs ? pose_weights(query.side, c.cell_m, c.range_m, s) : std::vector<float>{}),
        coarse_weights(weighs ? pose_weights((query.side + f - 1) / f, f * c.cell_m, c.range_m, s)
                              : std::vector<float>{}),
        full(pose_grid(query, 1, weights), m),
        coarse(pose_grid(query, f, coarse_weights), mc) {
    if (weighs) stored.emplace(merged_image(query, 1), m);
  }
  BirdsEyePlaceConfig config;
  BirdsEyeSearchConfig search;
  int m, f, mc;
  bool weighs;                                 // whether pose images differ from the stored ones
  std::vector<float> weights, coarse_weights;  // of the pose window, a cell each
  PaddedQuery full, coarse;                    // its pose images: what the pose is searched on
  std::optional<PaddedQuery> stored;  // the query as stored, when it differs: the pose's score
};

void validate(const BirdsEyeSearchConfig& search, const BirdsEyePlaceConfig& config) {
  if (!(search.max_shift_m >= 0 && search.max_shift_m <= 2 * config.range_m) ||
      search.yaw_steps < 0 || search.coarse_cells < 1 || search.refined_peaks < 1 ||
      search.finalists < 1 || !(search.pose_window_start_m >= 0) ||
      !(search.pose_window_end_m > search.pose_window_start_m)) {
    throw std::invalid_argument(
        "birds_eye: 0 <= max_shift_m <= 2 range_m, yaw_steps >= 0, coarse_cells >= 1, "
        "refined_peaks >= 1, finalists >= 1 and pose_window_end_m > pose_window_start_m >= 0 "
        "expected");
  }
}

BirdsEyeImageSearch::BirdsEyeImageSearch(const BirdsEyePlace& query,
                                         const BirdsEyePlaceConfig& config,
                                         const BirdsEyeSearchConfig& search) {
  validate(config);
  validate(search, config);
  check_image(query, config);
  prepared_ = std::make_shared<const Prepared>(query, config, search);
}

BirdsEyePose BirdsEyeImageSearch::pose(const BirdsEyePlace& stored, double key_yaw_rad) const {
  const Prepared& q = *prepared_;
  const BirdsEyePlaceConfig& config = q.config;
  check_image(stored, config);
  const int m = q.m, f = q.f, mc = q.mc;
  std::vector<double> yaws;
  for (double base : {key_yaw_rad, key_yaw_rad + M_PI}) {
    for (int k = -q.search.yaw_steps; k <= q.search.yaw_steps; ++k) {
      yaws.push_back(wrap_angle(base + k * M_PI / config.angles));
    }
  }
  const BorderedImage bordered(merged_image(stored, 1));
  // Full resolution, each yaw's turned place once it is searched (as stored too, when the pose
  // images differ from the stored ones).
  std::vector<std::optional<TurnedPlace>> turned(yaws.size());
  std::vector<std::optional<Correlation>> correlations(yaws.size());
  BirdsEyePose best;
  best.score = -1;
  int best_yaw = 0, best_x = 0, best_z = 0;  // the best whole-cell pose
  auto search_window = [&](int y, const Window& window) {
    if (!correlations[y]) {
      TurnedPlace t = turned_image(bordered, yaws[y], config.cell_m, config.range_m);
      if (q.weighs) {
        correlations[y].emplace(q.full, weighed(t, q.weights));
        turned[y] = std::move(t);
      } else {
        correlations[y].emplace(q.full, std::move(t));
      }
    }
    return peak_of(correlations[y]->window(window), window);
  };
  auto keep_if_better = [&](int y, const Peak& peak) {
    if (peak.score > best.score) {
      best = {peak.dx * config.cell_m, peak.dz * config.cell_m, yaws[y], peak.score};
      best_yaw = y, best_x = peak.x, best_z = peak.z;
    }
  };
  if (f == 1) {
    for (int y = 0; y < int(yaws.size()); ++y) keep_if_better(y, search_window(y, {-m, m, -m, m}));
  } else {
    // Coarse: the merged place turned on merged cells (the grid still starts at -range_m), so
    // a full-resolution peak at shift s lies within a cell or two of f times the merged one's.
    const BorderedImage coarse_place(merged_image(stored, f));
    std::vector<CoarsePeak> peaks;
    for (int y = 0; y < int(yaws.size()); ++y) {
      TurnedPlace turned_coarse =
          turned_image(coarse_place, yaws[y], f * config.cell_m, config.range_m);
      Correlation coarse(
          q.coarse, q.weighs ? weighed(turned_coarse, q.coarse_weights) : std::move(turned_coarse));
      local_maxima(coarse.window({-mc, mc, -mc, mc}), mc, y, peaks);
    }
    const std::size_t keep = std::min(peaks.size(), std::size_t(q.search.refined_peaks));
    std::partial_sort(peaks.begin(), peaks.begin() + std::ptrdiff_t(keep), peaks.end(),
                      [](const CoarsePeak& a, const CoarsePeak& b) { return a.score > b.score; });
    // Fine: (2f + 1)^2 shifts around f times each kept peak's shift (a merged cell blurs peaks
    // up to f cells apart), moved while the best lies off the window's centre: each move is
    // strictly uphill, so the climb ends at a local maximum, whose window then holds both
    // neighbours for the sub-cell refinement.
    for (std::size_t i = 0; i < keep; ++i) {
      int x = std::clamp(f * peaks[i].x, -m, m), z = std::clamp(f * peaks[i].z, -m, m);
      Peak peak;
      for (int moves = 0; moves <= 4 * m; ++moves) {
        const Window window{std::max(-m, x - f), std::min(m, x + f), std::max(-m, z - f),
                            std::min(m, z + f)};
        peak = search_window(peaks[i].yaw, window);
        if (peak.x == x && peak.z == z) break;
        x = peak.x;
        z = peak.z;
      }
      keep_if_better(peaks[i].yaw, peak);
    }
  }
  if (!(best.score > 0)) return {0, 0, wrap_angle(key_yaw_rad), 0, 0};
  best.fit = best.score;
  if (q.weighs) {
    Correlation as_stored(*q.stored, std::move(*turned[best_yaw]));
    best.score = as_stored.window({best_x, best_x, best_z, best_z})[0];
  }
  return best;
}

BirdsEyePose birds_eye_pose(const BirdsEyePlace& query, const BirdsEyePlace& place,
                            double key_yaw_rad, const BirdsEyePlaceConfig& config,
                            const BirdsEyeSearchConfig& search) {
  return BirdsEyeImageSearch(query, config, search).pose(place, key_yaw_rad);
}

std::vector<double> birds_eye_correlation(const BirdsEyePlace& query, const BirdsEyePlace& place,
                                          double yaw_rad, const BirdsEyePlaceConfig& config,
                                          int max_cells) {
  check_image(query, config);
  check_image(place, config);
  const Window all{-max_cells, max_cells, -max_cells, max_cells};
  const PaddedQuery padded(merged_image(query, 1), max_cells);
  return Correlation(padded, turned_image(BorderedImage(merged_image(place, 1)), yaw_rad,
                                          config.cell_m, config.range_m))
      .window(all);
}

std::vector<double> birds_eye_pose_correlation(const BirdsEyePlace& query,
                                               const BirdsEyePlace& place, double yaw_rad,
                                               const BirdsEyePlaceConfig& config,
                                               const BirdsEyeSearchConfig& search, int max_cells) {
  validate(config);
  validate(search, config);
  check_image(query, config);
  check_image(place, config);
  if (!pose_window_weighs(config, search)) {
    return birds_eye_correlation(query, place, yaw_rad, config, max_cells);
  }
  const std::vector<float> w = pose_weights(query.side, config.cell_m, config.range_m, search);
  const Window all{-max_cells, max_cells, -max_cells, max_cells};
  const PaddedQuery padded(weighed(merged_image(query, 1), w), max_cells);
  return Correlation(padded, weighed(turned_image(BorderedImage(merged_image(place, 1)), yaw_rad,
                                                  config.cell_m, config.range_m),
                                     w))
      .window(all);
}

}  // namespace loopscan
