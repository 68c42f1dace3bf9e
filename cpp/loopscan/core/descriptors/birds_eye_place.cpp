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

// log(1 + |2D DFT|) of the image zero-padded to n x n, at the frequencies the key samples:
// z frequency u in [0, band], x frequency v in [-band, band]. The image is real: rows go
// through real transforms, and only the columns of non-negative v are transformed, the others
// being point reflections (|F(-u, -v)| = |F(u, v)|).
class LogMagnitude {
 public:
  LogMagnitude(const std::vector<float>& image, int side, int n, int band)
      : band_(band), values_(std::size_t(band + 1) * std::size_t(2 * band + 1), 0.f) {
    const int cols = band + 1;  // v = 0 .. band
    std::vector<std::complex<float>> half(std::size_t(n) * std::size_t(cols));
    Eigen::FFT<float> real_fft, fft;
    real_fft.SetFlag(Eigen::FFT<float>::HalfSpectrum);
    std::vector<float> row(n, 0.f);
    std::vector<std::complex<float>> in(n), out(n);
    for (int r = 0; r < side; ++r) {  // rows beyond the image are zero and stay zero
      std::copy(image.begin() + std::ptrdiff_t(r) * side,
                image.begin() + std::ptrdiff_t(r + 1) * side, row.begin());
      real_fft.fwd(out, row);
      std::copy(out.begin(), out.begin() + cols, half.begin() + std::ptrdiff_t(r) * cols);
    }
    for (int c = 0; c < cols; ++c) {
      for (int r = 0; r < n; ++r) in[r] = half[std::size_t(r) * cols + c];
      fft.fwd(out, in);
      for (int u = 0; u <= band; ++u) {
        at(u, c) = std::log1p(std::abs(out[u]));
        if (c > 0) at(u, -c) = std::log1p(std::abs(out[(n - u) % n]));  // F(u, -c) = conj F(-u, c)
      }
    }
  }

  // Bilinear at fractional (u, v), u in [0, band - 1], v in [-band, band - 1].
  float sample(double u, double v) const {
    const double u0 = std::floor(u), v0 = std::floor(v), fu = u - u0, fv = v - v0;
    const int ui = int(u0), vi = int(v0);
    return float((1 - fu) * ((1 - fv) * value(ui, vi) + fv * value(ui, vi + 1)) +
                 fu * ((1 - fv) * value(ui + 1, vi) + fv * value(ui + 1, vi + 1)));
  }

 private:
  float& at(int u, int v) { return values_[std::size_t(u) * (2 * band_ + 1) + std::size_t(v + band_)]; }
  double value(int u, int v) const {
    return values_[std::size_t(u) * (2 * band_ + 1) + std::size_t(v + band_)];
  }

  int band_;
  std::vector<float> values_;  // (band + 1) x (2 band + 1)
};

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
  const double span = config.taper_end_m - config.taper_start_m, R = config.range_m;
  for (int r = 0; r < side_; ++r) {
    for (int c = 0; c < side_; ++c) {
      const double d = std::hypot((c + 0.5) * config.cell_m - R, (r + 0.5) * config.cell_m - R);
      const double w = std::clamp((config.taper_end_m - d) / span, 0.0, 1.0);
      const double s = std::sin(w * M_PI / 2);
      weights_[std::size_t(r) * side_ + c] = float(s * s);
    }
  }
}

std::vector<float> BirdsEyeDescriber::image(const float* x, const float* y, const float* z,
                                            std::size_t n) const {
  std::vector<float> image(std::size_t(side_) * side_, 0.f);
  const float inv = float(1.0 / config_.cell_m), R = float(config_.range_m);
  const float min_height = float(config_.min_height_m), limit = float(side_);
  const bool density = config_.cell == BirdsEyeCell::Density;
  for (std::size_t i = 0; i < n; ++i) {
    const float height = -y[i];
    const float fc = (x[i] + R) * inv, fr = (z[i] + R) * inv;
    // Negated tests also drop NaN coordinates and heights.
    if (!(height > min_height && fc >= 0.f && fc < limit && fr >= 0.f && fr < limit)) continue;
    float& v = image[std::size_t(fr) * side_ + std::size_t(fc)];  // truncation: floor here
    v = density ? v + 1.f : std::max(v, height - min_height);
  }
  for (std::size_t i = 0; i < image.size(); ++i) {
    if (image[i] == 0.f) continue;
    image[i] = (density ? std::sqrt(image[i]) : image[i]) * weights_[i];
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
  place.key.assign(std::size_t(config_.rings) * config_.angles, 0);
  if (!(top > 0)) return place;
  for (std::size_t i = 0; i < image.size(); ++i) {
    place.image[i] = std::uint8_t(std::lround(255.0 * image[i] / top));
  }
  const int N = config_.spectrum_size;
  const int band = int(std::ceil(config_.max_frequency)) + 1;  // bilinear reaches one bin out
  const LogMagnitude magnitude(image, place.side, N, band);
  std::vector<double> key(place.key.size());
  const double ring_step =
      config_.rings > 1 ? (config_.max_frequency - config_.min_frequency) / (config_.rings - 1) : 0;
  for (int ring = 0; ring < config_.rings; ++ring) {
    const double rho = config_.min_frequency + ring * ring_step;
    double mean = 0;
    for (int a = 0; a < config_.angles; ++a) {
      const double theta = a * M_PI / config_.angles;  // from the x axis towards z
      const double v = magnitude.sample(rho * std::sin(theta), rho * std::cos(theta));
      key[std::size_t(ring) * config_.angles + a] = v;
      mean += v;
    }
    mean /= config_.angles;
    for (int a = 0; a < config_.angles; ++a) key[std::size_t(ring) * config_.angles + a] -= mean;
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
