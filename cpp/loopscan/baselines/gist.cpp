#include "loopscan/baselines/gist.hpp"

#include <cmath>
#include <complex>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include <fftw3.h>
#include <opencv2/imgproc.hpp>

namespace loopscan::baselines {
namespace {

// Plans by FFTW_ESTIMATE: the same algorithm in every run, hence bit-identical descriptors
// (FFTW_MEASURE picks plans by timing, which changes the last bits from run to run, for ~15%
// more speed).
std::mutex& planner_mutex() {  // FFTW's planner is not thread-safe
  static std::mutex m;
  return m;
}

// Both reference programs pad 5 px before the prefilter; 7 gives a 270-point FFT (2 x 3^3 x 5),
// much faster than 266 (2 x 7 x 19) for the same purpose (keeping the low-pass from wrapping
// around). The reference variant keeps 5.
int prefilter_pad(const GistConfig& c) { return c.reference ? 5 : 7; }

// Signed frequency (cycles per sample) of FFT bin i of n.
double bin_frequency(int i, int n) {
  return (i < (n + 1) / 2 ? i : i - n) / static_cast<double>(n);
}

// Mirror (symmetric, edge pixel repeated) padding by `b` on every side.
cv::Mat mirror_pad(const cv::Mat& image, int b) {
  cv::Mat out;
  cv::copyMakeBorder(image, out, b, b, b, b, cv::BORDER_REFLECT);
  return out;
}

}  // namespace

// An n x n complex FFT pair with planned forward and inverse transforms.
// Out of place (faster than in place here): `data` -> `result`; `swap` moves the result back.
struct GistExtractor::Fft {
  int n;
  fftwf_complex *data, *result;
  fftwf_plan forward, inverse;
  explicit Fft(int size) : n(size) {
    data = static_cast<fftwf_complex*>(fftwf_malloc(sizeof(fftwf_complex) * n * n));
    result = static_cast<fftwf_complex*>(fftwf_malloc(sizeof(fftwf_complex) * n * n));
    std::lock_guard<std::mutex> lock(planner_mutex());
    forward = fftwf_plan_dft_2d(n, n, data, result, FFTW_FORWARD, FFTW_ESTIMATE);
    inverse = fftwf_plan_dft_2d(n, n, data, result, FFTW_BACKWARD, FFTW_ESTIMATE);
  }
  ~Fft() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftwf_destroy_plan(forward);
    fftwf_destroy_plan(inverse);
    fftwf_free(data);
    fftwf_free(result);
  }

  void load_real(const cv::Mat& m) {  // CV_32F, n x n
    for (int y = 0; y < n; ++y) {
      const float* row = m.ptr<float>(y);
      for (int x = 0; x < n; ++x) {
        data[y * n + x][0] = row[x];
        data[y * n + x][1] = 0.f;
      }
    }
  }
};

// Real n x n transforms (r2c / c2r, half spectrum n x (n/2 + 1)) for the prefilter's low-pass.
struct GistExtractor::RealFft {
  int n, half;
  float* real;
  fftwf_complex* spectrum;
  fftwf_plan forward, inverse;
  explicit RealFft(int size) : n(size), half(size / 2 + 1) {
    real = static_cast<float*>(fftwf_malloc(sizeof(float) * n * n));
    spectrum = static_cast<fftwf_complex*>(fftwf_malloc(sizeof(fftwf_complex) * n * half));
    std::lock_guard<std::mutex> lock(planner_mutex());
    forward = fftwf_plan_dft_r2c_2d(n, n, real, spectrum, FFTW_ESTIMATE);
    inverse = fftwf_plan_dft_c2r_2d(n, n, spectrum, real, FFTW_ESTIMATE);
  }
  ~RealFft() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftwf_destroy_plan(forward);
    fftwf_destroy_plan(inverse);
    fftwf_free(real);
    fftwf_free(spectrum);
  }
};

namespace {
GistConfig effective(GistConfig c) {
  if (c.reference) c.boundary = 0;
  return c;
}
}  // namespace

std::vector<GaborFilter> gabor_bank(const GistConfig& given) {
  const GistConfig c = effective(given);
  if (c.scales < 1 || c.orientations < 1 || c.image_size < 8 || c.boundary < 0 || c.grid < 1)
    throw std::invalid_argument("GIST: scales, orientations, grid >= 1, image size >= 8");
  const int n = c.image_size + 2 * c.boundary;
  // LMgist's parameters: bandwidth 0.35, peak 0.3 / 1.85^scale cycles per pixel, angular
  // sharpness 16 * orientations^2 / 32^2.
  const double sharpness = 16.0 * c.orientations * c.orientations / (32.0 * 32.0);
  std::vector<GaborFilter> bank;
  for (int s = 0; s < c.scales; ++s) {
    for (int o = 0; o < c.orientations; ++o) {
      GaborFilter g;
      g.scale = s;
      g.orientation = o;
      g.peak_cycles_per_pixel = 0.3 / std::pow(1.85, s);
      g.angle_rad = -M_PI / c.orientations * o;
      g.transfer.resize(static_cast<std::size_t>(n) * n);
      for (int y = 0; y < n; ++y) {
        const double fy = bin_frequency(y, n);
        for (int x = 0; x < n; ++x) {
          const double fx = bin_frequency(x, n);
          const double radius = std::hypot(fx, fy);
          double dt = std::atan2(fy, fx) + M_PI / c.orientations * o;
          if (dt < -M_PI) dt += 2 * M_PI;
          if (dt > M_PI) dt -= 2 * M_PI;
          const double r = radius / g.peak_cycles_per_pixel - 1.0;
          g.transfer[static_cast<std::size_t>(y) * n + x] =
              static_cast<float>(std::exp(-10.0 * 0.35 * r * r - 2.0 * sharpness * M_PI * dt * dt));
        }
      }
      bank.push_back(std::move(g));
    }
  }
  return bank;
}

GistExtractor::GistExtractor(const GistConfig& given)
    : config_(effective(given)),
      bank_(gabor_bank(config_)),
      prefilter_fft_(std::make_unique<RealFft>(config_.image_size + 2 * prefilter_pad(config_))),
      filter_fft_(std::make_unique<Fft>(config_.image_size + 2 * config_.boundary)) {
  // Prefilter low-pass: exp(-(fx^2 + fy^2) / s1^2), frequencies in cycles per image.
  const int np = prefilter_fft_->n, half = prefilter_fft_->half;
  const double s1 = config_.prefilter_fc / std::sqrt(std::log(2.0));
  prefilter_gauss_.resize(static_cast<std::size_t>(np) * half);
  for (int y = 0; y < np; ++y) {
    const double fy = bin_frequency(y, np) * np;
    for (int x = 0; x < half; ++x) {
      const double fx = static_cast<double>(x);
      // 1 / n^2 folds in the inverse transform's normalisation.
      prefilter_gauss_[static_cast<std::size_t>(y) * half + x] = static_cast<float>(
          std::exp(-(fx * fx + fy * fy) / (s1 * s1)) / (static_cast<double>(np) * np));
    }
  }
}

GistExtractor::~GistExtractor() = default;

cv::Mat cover_and_crop(const cv::Mat& gray, int size) {
  const double scale =
      std::max(static_cast<double>(size) / gray.cols, static_cast<double>(size) / gray.rows);
  // By scale factor, not by target size: OpenCV then samples at exactly 1 / scale (what the
  // authors' wrapper does; a target size would resample at cols / new_cols, a few pixels off).
  cv::Mat scaled;
  cv::resize(gray, scaled, cv::Size(), scale, scale, cv::INTER_LANCZOS4);
  if (scaled.cols < size || scaled.rows < size)
    cv::resize(gray, scaled, cv::Size(std::max(size, scaled.cols), std::max(size, scaled.rows)), 0,
               0, cv::INTER_LANCZOS4);
  return scaled(cv::Rect((scaled.cols - size) / 2, (scaled.rows - size) / 2, size, size)).clone();
}

Eigen::VectorXf GistExtractor::describe(const cv::Mat& input) {
  if (input.empty()) throw std::invalid_argument("GIST: empty image");
  cv::Mat gray = input;
  if (input.channels() == 3) cv::cvtColor(input, gray, cv::COLOR_BGR2GRAY);
  const int size = config_.image_size;
  cv::Mat img;
  if (config_.reference) {
    img = gray.cols == size && gray.rows == size ? gray.clone() : cover_and_crop(gray, size);
    img.convertTo(img, CV_32F);
  } else {
    cv::resize(gray, img, cv::Size(size, size), 0, 0, cv::INTER_AREA);
    img.convertTo(img, CV_32F);
    // Stretch to 0..255 as LMgist does (Lear's C GIST does not).
    double lo, hi;
    cv::minMaxLoc(img, &lo, &hi);
    if (hi > lo)
      img = (img - lo) * (255.0 / (hi - lo));
    else
      img.setTo(0);
  }
  cv::log(img + 1.0f, img);

  // Prefilter: whitening (subtract a Gaussian low-pass) and local contrast normalisation.
  RealFft& p = *prefilter_fft_;
  const int pad = prefilter_pad(config_), np = p.n;
  const cv::Mat padded = mirror_pad(img, pad);
  const std::vector<float>& gauss = prefilter_gauss_;
  auto low_pass = [&](const cv::Mat& m) {  // ifft(fft(m) .* gauss), real
    for (int y = 0; y < np; ++y)
      std::memcpy(p.real + static_cast<std::size_t>(y) * np, m.ptr<float>(y), sizeof(float) * np);
    fftwf_execute(p.forward);
    for (std::size_t i = 0; i < gauss.size(); ++i) {
      p.spectrum[i][0] *= gauss[i];
      p.spectrum[i][1] *= gauss[i];
    }
    fftwf_execute(p.inverse);
    return cv::Mat(np, np, CV_32F, p.real).clone();
  };
  cv::Mat white = padded - low_pass(padded);
  cv::Mat local = low_pass(white.mul(white));
  cv::sqrt(cv::abs(local), local);
  cv::Mat normalised = white / (0.2f + local);
  const cv::Mat pre = normalised(cv::Rect(pad, pad, size, size)).clone();

  // Gabor energies.
  Fft& f = *filter_fft_;
  const int b = config_.boundary, n = f.n;
  f.load_real(mirror_pad(pre, b));
  fftwf_execute(f.forward);
  std::vector<std::complex<float>> spectrum(static_cast<std::size_t>(n) * n);
  for (std::size_t i = 0; i < spectrum.size(); ++i) spectrum[i] = {f.result[i][0], f.result[i][1]};
  const int g = config_.grid;
  Eigen::VectorXf out(this->size());
  std::vector<double> cell(static_cast<std::size_t>(g) * g);
  // First column (and, the image being square, first row) of each grid cell.
  std::vector<int> column_start(static_cast<std::size_t>(g) + 1, size);
  for (int x = size - 1; x >= 0; --x) column_start[x * g / size] = x;
  std::vector<int> cell_pixels(cell.size());
  for (int cy = 0; cy < g; ++cy)
    for (int cx = 0; cx < g; ++cx)
      cell_pixels[static_cast<std::size_t>(cy) * g + cx] =
          (column_start[cy + 1] - column_start[cy]) * (column_start[cx + 1] - column_start[cx]);
  std::vector<float> magnitude(static_cast<std::size_t>(size));
  const double inv_n2 = 1.0 / (static_cast<double>(n) * n);
  for (std::size_t k = 0; k < bank_.size(); ++k) {
    const std::vector<float>& h = bank_[k].transfer;
    for (std::size_t i = 0; i < spectrum.size(); ++i) {
      f.data[i][0] = spectrum[i].real() * h[i];
      f.data[i][1] = spectrum[i].imag() * h[i];
    }
    fftwf_execute(f.inverse);
    std::fill(cell.begin(), cell.end(), 0.0);
    for (int y = 0; y < size; ++y) {
      const fftwf_complex* row = f.result + static_cast<std::size_t>(y + b) * n + b;
      for (int x = 0; x < size; ++x) magnitude[x] = row[x][0] * row[x][0] + row[x][1] * row[x][1];
      for (int x = 0; x < size; ++x) magnitude[x] = std::sqrt(magnitude[x]);
      double* cells = cell.data() + static_cast<std::size_t>(y * g / size) * g;
      // Each cell is a run of columns: one (vectorisable) sum per run.
      for (int c = 0; c < g; ++c) {
        float sum = 0.f;
        for (int x = column_start[c]; x < column_start[c + 1]; ++x) sum += magnitude[x];
        cells[c] += sum;
      }
    }
    for (double& e : cell) e *= inv_n2;
    for (int c = 0; c < g * g; ++c) {
      const int slot = config_.reference ? (c % g) * g + c / g : c;  // x-major in reference
      out[static_cast<Eigen::Index>(k) * g * g + slot] =
          static_cast<float>(cell[c] / cell_pixels[c]);
    }
  }
  return out;
}

}  // namespace loopscan::baselines
