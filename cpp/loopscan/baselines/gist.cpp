#include "loopscan/baselines/gist.hpp"

#include <cmath>
#include <complex>
#include <mutex>
#include <stdexcept>

#include <fftw3.h>
#include <opencv2/imgproc.hpp>

namespace loopscan::baselines {
namespace {

std::mutex& planner_mutex() {  // FFTW's planner is not thread-safe
  static std::mutex m;
  return m;
}

// Signed frequency (cycles per sample) of FFT bin i of n.
double bin_frequency(int i, int n) { return (i < (n + 1) / 2 ? i : i - n) / static_cast<double>(n); }

// Mirror (symmetric, edge pixel repeated) padding by `b` on every side.
cv::Mat mirror_pad(const cv::Mat& image, int b) {
  cv::Mat out;
  cv::copyMakeBorder(image, out, b, b, b, b, cv::BORDER_REFLECT);
  return out;
}

}  // namespace

// An n x n complex FFT pair with planned forward and inverse transforms.
struct GistExtractor::Fft {
  int n;
  fftwf_complex* data;
  fftwf_plan forward, inverse;
  explicit Fft(int size) : n(size) {
    data = static_cast<fftwf_complex*>(fftwf_malloc(sizeof(fftwf_complex) * n * n));
    std::lock_guard<std::mutex> lock(planner_mutex());
    forward = fftwf_plan_dft_2d(n, n, data, data, FFTW_FORWARD, FFTW_MEASURE);
    inverse = fftwf_plan_dft_2d(n, n, data, data, FFTW_BACKWARD, FFTW_MEASURE);
  }
  ~Fft() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftwf_destroy_plan(forward);
    fftwf_destroy_plan(inverse);
    fftwf_free(data);
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

std::vector<GaborFilter> gabor_bank(const GistConfig& c) {
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

GistExtractor::GistExtractor(const GistConfig& config)
    : config_(config),
      bank_(gabor_bank(config)),
      prefilter_fft_(std::make_unique<Fft>(config.image_size + 10)),
      filter_fft_(std::make_unique<Fft>(config.image_size + 2 * config.boundary)) {}

GistExtractor::~GistExtractor() = default;

Eigen::VectorXf GistExtractor::describe(const cv::Mat& input) {
  if (input.empty()) throw std::invalid_argument("GIST: empty image");
  cv::Mat gray = input;
  if (input.channels() == 3) cv::cvtColor(input, gray, cv::COLOR_BGR2GRAY);
  const int size = config_.image_size;
  cv::Mat img;
  cv::resize(gray, img, cv::Size(size, size), 0, 0, cv::INTER_AREA);
  img.convertTo(img, CV_32F);
  // Stretch to 0..255 as LMgist does, then log.
  double lo, hi;
  cv::minMaxLoc(img, &lo, &hi);
  if (hi > lo) img = (img - lo) * (255.0 / (hi - lo));
  else img.setTo(0);
  cv::log(img + 1.0f, img);

  // Prefilter: whitening (subtract a Gaussian low-pass) and local contrast normalisation.
  Fft& p = *prefilter_fft_;
  const int pad = 5, np = p.n;
  const cv::Mat padded = mirror_pad(img, pad);
  const double s1 = config_.prefilter_fc / std::sqrt(std::log(2.0));
  std::vector<float> gauss(static_cast<std::size_t>(np) * np);
  for (int y = 0; y < np; ++y) {
    const double fy = bin_frequency(y, np) * np;
    for (int x = 0; x < np; ++x) {
      const double fx = bin_frequency(x, np) * np;
      gauss[static_cast<std::size_t>(y) * np + x] =
          static_cast<float>(std::exp(-(fx * fx + fy * fy) / (s1 * s1)));
    }
  }
  auto low_pass = [&](const cv::Mat& m) {  // real part of ifft(fft(m) .* gauss)
    p.load_real(m);
    fftwf_execute(p.forward);
    const float scale = 1.0f / (static_cast<float>(np) * np);
    for (std::size_t i = 0; i < gauss.size(); ++i) {
      p.data[i][0] *= gauss[i] * scale;
      p.data[i][1] *= gauss[i] * scale;
    }
    fftwf_execute(p.inverse);
    cv::Mat out(np, np, CV_32F);
    for (int y = 0; y < np; ++y)
      for (int x = 0; x < np; ++x) out.at<float>(y, x) = p.data[y * np + x][0];
    return out;
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
  for (std::size_t i = 0; i < spectrum.size(); ++i) spectrum[i] = {f.data[i][0], f.data[i][1]};
  const int g = config_.grid;
  Eigen::VectorXf out(this->size());
  std::vector<double> cell(static_cast<std::size_t>(g) * g);
  std::vector<int> cell_pixels(cell.size(), 0);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) ++cell_pixels[static_cast<std::size_t>(y * g / size) * g + x * g / size];
  const float inv_n2 = 1.0f / (static_cast<float>(n) * n);
  for (std::size_t k = 0; k < bank_.size(); ++k) {
    const std::vector<float>& h = bank_[k].transfer;
    for (std::size_t i = 0; i < spectrum.size(); ++i) {
      f.data[i][0] = spectrum[i].real() * h[i];
      f.data[i][1] = spectrum[i].imag() * h[i];
    }
    fftwf_execute(f.inverse);
    std::fill(cell.begin(), cell.end(), 0.0);
    for (int y = 0; y < size; ++y) {
      const int cy = y * g / size;
      const fftwf_complex* row = f.data + static_cast<std::size_t>(y + b) * n + b;
      for (int x = 0; x < size; ++x) {
        cell[static_cast<std::size_t>(cy) * g + x * g / size] +=
            std::hypot(row[x][0], row[x][1]) * inv_n2;
      }
    }
    for (int c = 0; c < g * g; ++c)
      out[static_cast<Eigen::Index>(k) * g * g + c] = static_cast<float>(cell[c] / cell_pixels[c]);
  }
  return out;
}

}  // namespace loopscan::baselines
