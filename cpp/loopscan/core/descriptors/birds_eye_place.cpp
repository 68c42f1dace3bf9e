#include "loopscan/core/descriptors/birds_eye_place.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>

#include <unsupported/Eigen/FFT>

namespace loopscan {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("birds_eye: " + what);
}

// |2D DFT| of the image zero-padded to n x n, log-compressed, row-major (row = z frequency);
// only within `band` frequencies of zero in both axes (the key samples no others; zero there).
std::vector<float> log_magnitude(const std::vector<float>& image, int side, int n, int band) {
  std::vector<std::complex<float>> grid(std::size_t(n) * std::size_t(n));
  Eigen::FFT<float> fft;
  std::vector<std::complex<float>> in(n), out(n);
  for (int r = 0; r < side; ++r) {  // rows beyond the image are zero and stay zero
    std::fill(in.begin(), in.end(), std::complex<float>(0.f));
    for (int c = 0; c < side; ++c) in[c] = image[std::size_t(r) * side + c];
    fft.fwd(out, in);
    std::copy(out.begin(), out.end(), grid.begin() + std::ptrdiff_t(r) * n);
  }
  for (int c = 0; c < n; ++c) {
    if (std::min(c, n - c) > band) continue;
    for (int r = 0; r < n; ++r) in[r] = grid[std::size_t(r) * n + c];
    fft.fwd(out, in);
    for (int r = 0; r < n; ++r) grid[std::size_t(r) * n + c] = out[r];
  }
  std::vector<float> magnitude(grid.size(), 0.f);
  for (int r = 0; r < n; ++r) {
    if (std::min(r, n - r) > band) continue;
    for (int c = 0; c < n; ++c) {
      if (std::min(c, n - c) > band) continue;
      const std::size_t i = std::size_t(r) * n + c;
      magnitude[i] = std::log1p(std::abs(grid[i]));
    }
  }
  return magnitude;
}

// Bilinear sample of a periodic n x n grid at fractional (row, col).
float periodic_sample(const std::vector<float>& grid, int n, double row, double col) {
  const double r0 = std::floor(row), c0 = std::floor(col);
  const double fr = row - r0, fc = col - c0;
  auto at = [&](double r, double c) {
    const int ri = ((int(r) % n) + n) % n, ci = ((int(c) % n) + n) % n;
    return double(grid[std::size_t(ri) * n + ci]);
  };
  return float((1 - fr) * ((1 - fc) * at(r0, c0) + fc * at(r0, c0 + 1)) +
               fr * ((1 - fc) * at(r0 + 1, c0) + fc * at(r0 + 1, c0 + 1)));
}

}  // namespace

void validate(const BirdsEyePlaceConfig& c) {
  require(std::isfinite(c.cell_m) && c.cell_m > 0, "cell_m must be positive");
  require(std::isfinite(c.range_m) && c.range_m >= c.cell_m, "range_m must be >= cell_m");
  require(c.taper_start_m >= 0 && c.taper_end_m > c.taper_start_m,
          "taper_end_m must exceed taper_start_m >= 0");
  require(std::isfinite(c.min_height_m), "min_height_m must be finite");
  require(c.rings >= 1 && c.angles >= 2, "rings >= 1 and angles >= 2");
  require(c.min_frequency >= 0 && c.max_frequency >= c.min_frequency &&
              c.max_frequency <= c.spectrum_size / 2.0,
          "0 <= min_frequency <= max_frequency <= spectrum_size / 2");
  require(c.spectrum_size >= image_side(c) && c.spectrum_size <= 4096,
          "spectrum_size must hold the image (2 range_m / cell_m cells) and be <= 4096");
}

int image_side(const BirdsEyePlaceConfig& c) {
  return std::max(1, int(std::lround(2.0 * c.range_m / c.cell_m)));
}

std::vector<float> birds_eye_image(const float* x, const float* y, const float* z, std::size_t n,
                                   const BirdsEyePlaceConfig& config) {
  const int side = image_side(config);
  std::vector<float> image(std::size_t(side) * side, 0.f);
  const double inv = 1.0 / config.cell_m, R = config.range_m;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(-double(y[i]) > config.min_height_m)) continue;  // also drops NaN heights
    const double c = std::floor((double(x[i]) + R) * inv), r = std::floor((double(z[i]) + R) * inv);
    if (!(c >= 0 && c < side && r >= 0 && r < side)) continue;
    float& v = image[std::size_t(r) * side + std::size_t(c)];
    if (config.cell == BirdsEyeCell::Density) {
      v += 1.f;
    } else {
      v = std::max(v, float(-double(y[i]) - config.min_height_m));
    }
  }
  const double span = config.taper_end_m - config.taper_start_m;
  for (int r = 0; r < side; ++r) {
    for (int c = 0; c < side; ++c) {
      float& v = image[std::size_t(r) * side + c];
      if (v == 0.f) continue;
      const double d = std::hypot((c + 0.5) * config.cell_m - R, (r + 0.5) * config.cell_m - R);
      const double w = std::clamp((config.taper_end_m - d) / span, 0.0, 1.0);
      const double s = std::sin(w * M_PI / 2);
      const double value = config.cell == BirdsEyeCell::Density ? std::sqrt(double(v)) : double(v);
      v = float(value * s * s);
    }
  }
  return image;
}

BirdsEyePlace describe_birds_eye(const float* x, const float* y, const float* z, std::size_t n,
                                 const BirdsEyePlaceConfig& config) {
  validate(config);
  BirdsEyePlace place;
  place.side = image_side(config);
  const std::vector<float> image = birds_eye_image(x, y, z, n, config);
  const float top = *std::max_element(image.begin(), image.end());
  place.image.assign(image.size(), 0);
  place.key.assign(std::size_t(config.rings) * config.angles, 0);
  if (!(top > 0)) return place;
  for (std::size_t i = 0; i < image.size(); ++i) {
    place.image[i] = std::uint8_t(std::lround(255.0 * image[i] / top));
  }
  const int N = config.spectrum_size;
  const int band = int(std::ceil(config.max_frequency)) + 1;  // bilinear reaches one bin out
  const std::vector<float> magnitude = log_magnitude(image, place.side, N, band);
  std::vector<double> key(place.key.size());
  const double ring_step =
      config.rings > 1 ? (config.max_frequency - config.min_frequency) / (config.rings - 1) : 0;
  for (int ring = 0; ring < config.rings; ++ring) {
    const double rho = config.min_frequency + ring * ring_step;
    double mean = 0;
    for (int a = 0; a < config.angles; ++a) {
      const double theta = a * M_PI / config.angles;  // from the x axis towards z
      const double v = periodic_sample(magnitude, N, rho * std::sin(theta), rho * std::cos(theta));
      key[std::size_t(ring) * config.angles + a] = v;
      mean += v;
    }
    mean /= config.angles;
    for (int a = 0; a < config.angles; ++a) key[std::size_t(ring) * config.angles + a] -= mean;
  }
  double peak = 0;
  for (double v : key) peak = std::max(peak, std::abs(v));
  if (peak > 0) {
    for (std::size_t i = 0; i < key.size(); ++i) {
      place.key[i] = std::int8_t(std::lround(127.0 * key[i] / peak));
    }
  }
  return place;
}

}  // namespace loopscan
