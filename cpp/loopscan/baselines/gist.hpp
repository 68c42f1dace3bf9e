#pragma once
// GIST (Oliva & Torralba 2001), as in the authors' LMgist: the gray image resized to 256x256,
// log and local contrast normalisation (prefilter, fc = 4 cycles/image), a bank of Gabor filters
// (4 scales x 8 orientations) applied in the frequency domain on the image mirrored by 32 px,
// and the filter energies |response| averaged on a 4x4 grid: 512 values, compared by Euclidean
// distance. FFTs by FFTW3 (single precision).
//
// Layout of the descriptor: filter-major (scale 0 orientations 0..7, scale 1, ...), then the
// 4x4 grid row by row (top row first); the reference variant column by column.
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace loopscan::baselines {

struct GistConfig {
  int image_size = 256;  // the image is resized (not cropped) to image_size x image_size
  int scales = 4, orientations = 8;
  int grid = 4;
  int boundary = 32;  // mirrored border around the image before filtering
  double prefilter_fc = 4.0;
  // Lear's C GIST as the paper's authors call it (`--mode reference`): the image scaled to
  // cover image_size x image_size (OpenCV Lanczos-4) and centre-cropped instead of resized
  // with distortion, no 0..255 stretch before the log, and the grid cells column by column
  // (x-major, as both reference programs store them); Lear's filters act on the image itself
  // (circular, no mirrored border: `boundary` is ignored) after a 5 px prefilter pad.
  bool reference = false;
  static GistConfig lear_c() {
    GistConfig c;
    c.reference = true;
    return c;
  }
};

// The reference variant's preprocessing: scaled by one factor (Lanczos-4) so that the smaller
// side is `size`, then the centred size x size window.
cv::Mat cover_and_crop(const cv::Mat& gray, int size);

// One Gabor filter's transfer function on an n x n frequency grid (unshifted: index (0, 0) is
// the zero frequency), with its nominal peak.
struct GaborFilter {
  int scale = 0, orientation = 0;
  double peak_cycles_per_pixel = 0;  // radial frequency of the peak
  double angle_rad = 0;              // direction of the peak in the frequency plane
  std::vector<float> transfer;       // n * n, row-major (y then x)
};

std::vector<GaborFilter> gabor_bank(const GistConfig& config);

// Not thread-safe (owns FFTW plans and buffers); use one per thread.
class GistExtractor {
 public:
  explicit GistExtractor(const GistConfig& config = {});
  ~GistExtractor();
  GistExtractor(const GistExtractor&) = delete;
  GistExtractor& operator=(const GistExtractor&) = delete;

  // `image`: 8-bit gray (or 3-channel, converted), any size.
  Eigen::VectorXf describe(const cv::Mat& image);
  int size() const { return config_.scales * config_.orientations * config_.grid * config_.grid; }
  const GistConfig& config() const { return config_; }

 private:
  struct Fft;
  struct RealFft;
  GistConfig config_;
  std::vector<GaborFilter> bank_;
  std::vector<float> prefilter_gauss_;
  std::unique_ptr<RealFft> prefilter_fft_;
  std::unique_ptr<Fft> filter_fft_;
};

}  // namespace loopscan::baselines
