#include "loopscan/core/descriptors/birds_eye_place.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("birds_eye: " + what);
}

// log(1 + x) for x >= 0 within ~1e-7 of the exact value, lane by lane: y = 1 + x = 2^e m with
// m in [sqrt(1/2), sqrt(2)), and log m = 2 atanh(s), s = (m - 1) / (m + 1), |s| < 0.172, as a
// series to s^9.
template <class V, class I>
LOOPSCAN_INLINE V log1p_nonnegative(V x) {
  const V y = 1.f + x;
  const I bits = I(y);  // the same bits
  I e = (bits >> 23) - 127;
  V m = V((bits & 0x007fffff) | 0x3f800000);  // in [1, 2)
  const I high = m > 1.41421356f;             // all ones where true
  m = V((I(0.5f * m) & high) | (I(m) & ~high));
  e -= high;
  const V s = (m - 1.f) / (m + 1.f), s2 = s * s;
  const V series = 1.f + s2 * (1.f / 3 + s2 * (1.f / 5 + s2 * (1.f / 7 + s2 * (1.f / 9))));
  return __builtin_convertvector(e, V) * 0.693147181f + 2.f * s * series;
}

// Where points land on the image: cell = row * side + column, or -1 for a point below the
// structure height, outside the image or not finite; rise = its height over min_height_m.
struct PointCells {
  float inv_cell, range, min_height, limit;
  int side;
};

template <int W>
LOOPSCAN_INLINE void point_cells_impl(const PointCells& p, const float* x, const float* y,
                                      const float* z, std::size_t count, int* cell, float* rise) {
  using V = typename simd::Vec<float, W>::type;
  using I = typename simd::Vec<std::int32_t, W>::type;
  constexpr int L = simd::Vec<float, W>::kLanes;
  std::size_t k = 0;
  for (; k + L <= count; k += L) {
    const V height = -simd::load<V>(y + k);
    const V fc = (simd::load<V>(x + k) + p.range) * p.inv_cell;
    const V fr = (simd::load<V>(z + k) + p.range) * p.inv_cell;
    // Ordered comparisons: NaN fails them all.
    const I used =
        (height > p.min_height) & (fc >= 0.f) & (fc < p.limit) & (fr >= 0.f) & (fr < p.limit);
    const I column = __builtin_convertvector(V(I(fc) & used), I);  // truncation: floor here
    const I row = __builtin_convertvector(V(I(fr) & used), I);
    simd::store(cell + k, (row * p.side + column) | ~used);
    simd::store(rise + k, height - p.min_height);
  }
  for (; k < count; ++k) {
    const float height = -y[k];
    const float fc = (x[k] + p.range) * p.inv_cell, fr = (z[k] + p.range) * p.inv_cell;
    const bool used =
        height > p.min_height && fc >= 0.f && fc < p.limit && fr >= 0.f && fr < p.limit;
    cell[k] = used ? int(fr) * p.side + int(fc) : -1;
    rise[k] = height - p.min_height;
  }
}

void point_cells_base(const PointCells& p, const float* x, const float* y, const float* z,
                      std::size_t count, int* cell, float* rise) {
  point_cells_impl<16>(p, x, y, z, count, cell, rise);
}
#if LOOPSCAN_HAVE_AVX2_CLONES
LOOPSCAN_AVX2 void point_cells_avx2(const PointCells& p, const float* x, const float* y,
                                    const float* z, std::size_t count, int* cell, float* rise) {
  point_cells_impl<32>(p, x, y, z, count, cell, rise);
}
#endif

void point_cells(const PointCells& p, const float* x, const float* y, const float* z,
                 std::size_t count, int* cell, float* rise) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const auto kernel = simd::has_avx2() ? point_cells_avx2 : point_cells_base;
#else
  static const auto kernel = point_cells_base;
#endif
  kernel(p, x, y, z, count, cell, rise);
}

// The image's 2D DFT (zero-padded to N x N: the tables hold N) at z frequencies u in [0, band]
// and x frequencies v in [-band, band], as log(1 + |F|) on a (band + 1) x (2 band + 1) grid.
// A direct transform over the non-zero cells: only the band's frequencies are needed, and the
// tapered image is partly empty. Rows first, H(r, v) = sum_c I(r, c) e^{-2 pi i c v / N};
// then, with A = sum_r cos(2 pi u r / N) Re H, B = sum_r sin(..) Im H, C = sum_r cos(..) Im H
// and D = sum_r sin(..) Re H, F(u, v) = (A + B) + i (C - D) and F(-u, v) = (A - B) + i (C + D),
// and |F(u, -v)| = |F(-u, v)| for a real image.
template <int W>
LOOPSCAN_INLINE void log_magnitude_impl(const float* image, int side, int band, int stride,
                                        const float* row_table, const float* column_cos,
                                        const float* column_sin, float* grid) {
  using V = typename simd::Vec<float, W>::type;
  constexpr int L = simd::Vec<float, W>::kLanes;
  const int blocks = stride / L, terms = band + 1, width = 2 * band + 1;
  std::vector<float> h(std::size_t(side) * 2 * stride, 0.f);
  std::vector<int> rows;  // rows with structure
  for (int r = 0; r < side; ++r) {
    float* hr = h.data() + std::size_t(r) * 2 * stride;
    bool any = false;
    for (int c = 0; c < side; ++c) {
      const float value = image[std::size_t(r) * side + c];
      if (value == 0.f) continue;
      any = true;
      const float* t = row_table + std::size_t(c) * 2 * stride;
      for (int b = 0; b < 2 * blocks; ++b) {
        simd::store(hr + b * L, simd::load<V>(hr + b * L) + value * simd::load<V>(t + b * L));
      }
    }
    if (any) rows.push_back(r);
  }
  std::vector<float> sums(std::size_t(4) * terms * stride);
  for (int u = 0; u < terms; ++u) {
    for (int b = 0; b < blocks; ++b) {
      V a{}, bs{}, c{}, d{};
      for (int r : rows) {
        const float* hr = h.data() + std::size_t(r) * 2 * stride + b * L;
        const V re = simd::load<V>(hr), im = simd::load<V>(hr + stride);
        const float zc = column_cos[std::size_t(u) * side + r];
        const float zs = column_sin[std::size_t(u) * side + r];
        a += zc * re;
        bs += zs * im;
        c += zc * im;
        d += zs * re;
      }
      const std::size_t at = std::size_t(u) * stride + b * L;
      simd::store(&sums[at], a);
      simd::store(&sums[std::size_t(terms) * stride + at], bs);
      simd::store(&sums[std::size_t(2) * terms * stride + at], c);
      simd::store(&sums[std::size_t(3) * terms * stride + at], d);
    }
  }
  const float* A = sums.data();
  const float* B = A + std::size_t(terms) * stride;
  const float* C = B + std::size_t(terms) * stride;
  const float* D = C + std::size_t(terms) * stride;
  // |F| of u >= 0 (positive) and u < 0 (negative) per frequency, then their logs, in loops
  // that vectorise.
  std::vector<float> magnitude(std::size_t(2) * terms * stride);
  for (std::size_t i = 0; i < std::size_t(terms) * stride; ++i) {
    const float re = A[i] + B[i], im = C[i] - D[i];
    const float re_negative = A[i] - B[i], im_negative = C[i] + D[i];
    magnitude[2 * i] = std::sqrt(re * re + im * im);
    magnitude[2 * i + 1] = std::sqrt(re_negative * re_negative + im_negative * im_negative);
  }
  using I = typename simd::Vec<std::int32_t, W>::type;
  for (std::size_t i = 0; i < magnitude.size(); i += L) {  // 2 terms stride: whole vectors
    simd::store(&magnitude[i], log1p_nonnegative<V, I>(simd::load<V>(&magnitude[i])));
  }
  for (int u = 0; u < terms; ++u) {
    float* row = grid + std::size_t(u) * width + band;  // v = 0
    const float* m = magnitude.data() + std::size_t(2) * u * stride;
    for (int v = 0; v <= band; ++v) row[v] = m[2 * v];
    for (int v = 1; v <= band; ++v) row[-v] = m[2 * v + 1];
  }
}

void log_magnitude_base(const float* image, int side, int band, int stride, const float* row_table,
                        const float* column_cos, const float* column_sin, float* grid) {
  log_magnitude_impl<16>(image, side, band, stride, row_table, column_cos, column_sin, grid);
}
#if LOOPSCAN_HAVE_AVX2_CLONES
LOOPSCAN_AVX2 void log_magnitude_avx2(const float* image, int side, int band, int stride,
                                      const float* row_table, const float* column_cos,
                                      const float* column_sin, float* grid) {
  log_magnitude_impl<32>(image, side, band, stride, row_table, column_cos, column_sin, grid);
}
#endif

void log_magnitude(const float* image, int side, int band, int stride, const float* row_table,
                   const float* column_cos, const float* column_sin, float* grid) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const auto kernel = simd::has_avx2() ? log_magnitude_avx2 : log_magnitude_base;
#else
  static const auto kernel = log_magnitude_base;
#endif
  kernel(image, side, band, stride, row_table, column_cos, column_sin, grid);
}

}  // namespace

std::string birds_eye_cell_name(BirdsEyeCell cell) {
  return cell == BirdsEyeCell::Height ? "height" : "density";
}

BirdsEyeCell parse_birds_eye_cell(const std::string& name) {
  if (name == "density") return BirdsEyeCell::Density;
  if (name == "height") return BirdsEyeCell::Height;
  throw std::invalid_argument("bird's-eye cell '" + name + "': density or height expected");
}

void validate(const BirdsEyePlaceConfig& c) {
  require(std::isfinite(c.cell_m) && c.cell_m > 0, "cell_m must be positive");
  require(std::isfinite(c.range_m) && c.range_m >= c.cell_m, "range_m must be >= cell_m");
  require(c.taper_start_m >= 0 && c.taper_end_m > c.taper_start_m,
          "taper_end_m must exceed taper_start_m >= 0");
  require(std::isfinite(c.min_height_m), "min_height_m must be finite");
  require(c.rings >= 1 && c.angles >= 2 && c.angles <= 720, "rings >= 1 and 2 <= angles <= 720");
  // The key's bilinear samples reach one frequency past max_frequency, below Nyquist.
  require(c.min_frequency >= 0 && c.max_frequency >= c.min_frequency &&
              c.max_frequency <= c.spectrum_size / 2.0 - 1,
          "0 <= min_frequency <= max_frequency <= spectrum_size / 2 - 1");
  require(c.spectrum_size >= image_side(c) && c.spectrum_size <= 4096,
          "spectrum_size must hold the image (2 range_m / cell_m cells) and be <= 4096");
}

BirdsEyeDescriber::BirdsEyeDescriber(const BirdsEyePlaceConfig& config) : config_(config) {
  validate(config);
  side_ = image_side(config);
  weights_.assign(std::size_t(side_) * side_, 0.f);
  const double R = config.range_m;
  for (int r = 0; r < side_; ++r) {
    for (int c = 0; c < side_; ++c) {
      const double d = std::hypot((c + 0.5) * config.cell_m - R, (r + 0.5) * config.cell_m - R);
      weights_[std::size_t(r) * side_ + c] =
          float(birds_eye_window_weight(d, config.taper_start_m, config.taper_end_m));
    }
  }
  density_table_.resize(1024);
  for (std::size_t n = 0; n < density_table_.size(); ++n) {
    density_table_[n] = float(std::log1p(0.5 * double(n)));
  }
  const int N = config.spectrum_size;
  band_ = int(std::ceil(config.max_frequency)) + 1;  // bilinear samples reach one bin out
  const int terms = band_ + 1;
  stride_ = (terms + 15) / 16 * 16;
  auto turn = [N](long long a, long long b) { return 2 * M_PI * double(a * b % N) / N; };
  row_table_.assign(std::size_t(side_) * 2 * stride_, 0.f);
  column_cos_.assign(std::size_t(terms) * side_, 0.f);
  column_sin_.assign(std::size_t(terms) * side_, 0.f);
  for (int c = 0; c < side_; ++c) {
    for (int v = 0; v < terms; ++v) {
      row_table_[std::size_t(c) * 2 * stride_ + v] = float(std::cos(turn(c, v)));
      row_table_[std::size_t(c) * 2 * stride_ + stride_ + v] = float(-std::sin(turn(c, v)));
    }
  }
  for (int u = 0; u < terms; ++u) {
    for (int r = 0; r < side_; ++r) {
      column_cos_[std::size_t(u) * side_ + r] = float(std::cos(turn(u, r)));
      column_sin_[std::size_t(u) * side_ + r] = float(std::sin(turn(u, r)));
    }
  }
  const int width = 2 * band_ + 1;
  const double ring_step =
      config.rings > 1 ? (config.max_frequency - config.min_frequency) / (config.rings - 1) : 0;
  samples_.resize(std::size_t(config.rings) * config.angles);
  for (int ring = 0; ring < config.rings; ++ring) {
    const double rho = config.min_frequency + ring * ring_step;
    for (int a = 0; a < config.angles; ++a) {
      const double theta = a * M_PI / config.angles;  // from the x axis towards z
      const double u = rho * std::sin(theta), v = rho * std::cos(theta);
      const double u0 = std::floor(u), v0 = std::floor(v);
      samples_[std::size_t(ring) * config.angles + a] = {int(u0) * width + int(v0) + band_,
                                                         float(u - u0), float(v - v0)};
    }
  }
}

std::vector<float> BirdsEyeDescriber::image(const float* x, const float* y, const float* z,
                                            std::size_t n) const {
  const std::size_t cells = std::size_t(side_) * side_;
  const float inv = float(1.0 / config_.cell_m), R = float(config_.range_m);
  const float min_height = float(config_.min_height_m), limit = float(side_);
  const bool density = config_.cell == BirdsEyeCell::Density;
  // In blocks: each point's cell by a vector kernel, then the sums without branches: unused
  // points land in a spare cell, and counts alternate between two histograms so that points
  // of one cell in a row do not wait for each other's stores.
  std::vector<float> image(2 * (cells + 1), 0.f);
  constexpr std::size_t kBlock = 256;
  alignas(64) int cell[kBlock];
  alignas(64) float rise[kBlock];
  const PointCells where{inv, R, min_height, limit, side_};
  float* even = image.data();
  float* odd = image.data() + cells + 1;
  for (std::size_t begin = 0; begin < n; begin += kBlock) {
    const std::size_t count = std::min(kBlock, n - begin);
    point_cells(where, x + begin, y + begin, z + begin, count, cell, rise);
    for (std::size_t k = 0; k < count; ++k) {
      cell[k] = cell[k] < 0 ? int(cells) : cell[k];
    }
    if (density) {
      std::size_t k = 0;
      for (; k + 2 <= count; k += 2) {
        even[cell[k]] += 1.f;
        odd[cell[k + 1]] += 1.f;
      }
      if (k < count) even[cell[k]] += 1.f;
    } else {
      for (std::size_t k = 0; k < count; ++k) even[cell[k]] = std::max(even[cell[k]], rise[k]);
    }
  }
  if (density) {
    for (std::size_t i = 0; i < cells; ++i) even[i] += odd[i];
  }
  image.resize(cells);
  for (std::size_t i = 0; i < image.size(); ++i) {
    if (image[i] == 0.f) continue;
    image[i] = (density ? density_value(image[i]) : image[i]) * weights_[i];
  }
  return image;
}

BirdsEyePlace describe_birds_eye(const float* x, const float* y, const float* z, std::size_t n,
                                 const BirdsEyePlaceConfig& config) {
  return BirdsEyeDescriber(config).describe(x, y, z, n);
}

BirdsEyePlace BirdsEyeDescriber::describe(const float* x, const float* y, const float* z,
                                          std::size_t n) const {
  BirdsEyePlace place;
  place.side = side_;
  const std::vector<float> image = this->image(x, y, z, n);
  const float top = *std::max_element(image.begin(), image.end());
  place.image.assign(image.size(), 0);
  place.key.assign(samples_.size(), 0);
  if (!(top > 0)) return place;
  const float to_byte = 255.f / top;
  for (std::size_t i = 0; i < image.size(); ++i) {
    place.image[i] = std::uint8_t(image[i] * to_byte + 0.5f);  // values >= 0: rounds to nearest
  }
  const int width = 2 * band_ + 1;
  std::vector<float> grid(std::size_t(band_ + 1) * width);
  log_magnitude(image.data(), side_, band_, stride_, row_table_.data(), column_cos_.data(),
                column_sin_.data(), grid.data());
  std::vector<float> key(samples_.size());
  for (std::size_t k = 0; k < samples_.size(); ++k) {
    const KeySample& s = samples_[k];
    const float* g = grid.data() + s.bin;
    key[k] = (1 - s.fu) * ((1 - s.fv) * g[0] + s.fv * g[1]) +
             s.fu * ((1 - s.fv) * g[width] + s.fv * g[width + 1]);
  }
  float peak = 0;
  for (int ring = 0; ring < config_.rings; ++ring) {
    float* values = key.data() + std::size_t(ring) * config_.angles;
    double mean = 0;
    for (int a = 0; a < config_.angles; ++a) mean += values[a];
    const float m = float(mean / config_.angles);
    for (int a = 0; a < config_.angles; ++a) {
      values[a] -= m;
      peak = std::max(peak, std::abs(values[a]));
    }
  }
  if (peak > 0) {
    const float to_int8 = 127.f / peak;
    for (std::size_t i = 0; i < key.size(); ++i) {
      place.key[i] = std::int8_t(std::lrint(key[i] * to_int8));
    }
  }
  return place;
}

Signature birds_eye_signature(const BirdsEyePlace& place) {
  Signature s(1, static_cast<Eigen::Index>(place.image.size() + place.key.size()));
  Eigen::Index c = 0;
  for (std::uint8_t v : place.image) s(0, c++) = v;
  for (std::int8_t v : place.key) s(0, c++) = v;
  return s;
}

BirdsEyePlace birds_eye_place(const double* values, int columns,
                              const BirdsEyePlaceConfig& config) {
  const int side = image_side(config), cells = side * side;
  const int expected = birds_eye_signature_columns(config);
  require(columns == expected, "a place signature holds " + std::to_string(expected) +
                                   " values (image " + std::to_string(side) + " x " +
                                   std::to_string(side) + ", key " + std::to_string(config.rings) +
                                   " x " + std::to_string(config.angles) + "), got " +
                                   std::to_string(columns));
  auto whole_in = [&](int c, double lo, double hi) {
    const double v = values[c];
    if (!(v >= lo && v <= hi && v == std::floor(v))) {  // the message only when it is needed
      require(false, "signature value " + std::to_string(c) + " is " + std::to_string(v) +
                         ", expected a whole number in [" + std::to_string(int(lo)) + ", " +
                         std::to_string(int(hi)) + "]");
    }
    return static_cast<int>(v);
  };
  BirdsEyePlace place;
  place.side = side;
  place.image.resize(cells);
  place.key.resize(static_cast<std::size_t>(config.rings) * config.angles);
  for (int c = 0; c < cells; ++c) place.image[c] = static_cast<std::uint8_t>(whole_in(c, 0, 255));
  for (std::size_t k = 0; k < place.key.size(); ++k) {
    place.key[k] = static_cast<std::int8_t>(whole_in(cells + static_cast<int>(k), -127, 127));
  }
  return place;
}

BirdsEyePlace birds_eye_place(const Signature& signature, const BirdsEyePlaceConfig& config) {
  require(signature.rows() == 1, "a place signature is one row, got " +
                                     std::to_string(signature.rows()));
  const Eigen::RowVectorXd row = signature.row(0);
  return birds_eye_place(row.data(), static_cast<int>(row.size()), config);
}

}  // namespace loopscan
