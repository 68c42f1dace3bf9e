#pragma once
// A place seen from above, one descriptor for any driving direction and lane. The image is the
// density of structure points on the ground plane around the keyframe. The key is the magnitude
// of the image's 2D Fourier transform, resampled on a polar grid: a translation of the place
// (the other lane, a keyframe metres along) leaves the magnitude alone, and a turn of the place
// shifts the key along its angles. One circular correlation of two keys therefore compares
// places seen from anywhere nearby, in any direction, and gives their yaw; the images then give
// the metric offset (birds_eye_match.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "loopscan/core/signature.hpp"

namespace loopscan {

// What a cell of the image holds: log(1 + n / 2) of its n structure points (how much was seen
// there; the better within one season), or the height of its highest point over min_height_m
// (what stands there, whatever the density of the VO's points; the better across seasons).
// The logarithm is nearly linear in the few points a polar-filtered scan leaves in a cell and
// compresses the many a dense VO or a summer tree leaves.
enum class BirdsEyeCell { Density, Height };
// "density" | "height"; parse throws std::invalid_argument on anything else.
std::string birds_eye_cell_name(BirdsEyeCell cell);
BirdsEyeCell parse_birds_eye_cell(const std::string& name);

struct BirdsEyePlaceConfig {
  BirdsEyeCell cell = BirdsEyeCell::Density;
  double cell_m = 1.0;
  double range_m = 30.0;        // the image spans [-range_m, range_m] in x and z
  // Cell weights fall smoothly from 1 at taper_start_m to 0 at taper_end_m: a round window, so
  // that a turned place moves its key along the angles. Near structure weighs most: it fixes
  // the pose along a street (a flat window recognises more across seasons and in repeating
  // streets, and needs BirdsEyeSearchConfig's pose window to keep the pose).
  double taper_start_m = 10.0;
  double taper_end_m = 30.0;
  double min_height_m = -1.0;   // structure: points above this height over the camera (up +)
  int spectrum_size = 128;      // the image is zero-padded to this side for the transform
  int rings = 24;               // key radii, evenly spaced over [min_frequency, max_frequency]
  int angles = 60;              // key angles over [0, pi): the magnitude is point-symmetric
  double min_frequency = 3.0;   // cycles per spectrum_size cells
  double max_frequency = 30.0;
};

// Throws std::invalid_argument naming the first bad field.
void validate(const BirdsEyePlaceConfig& config);

// The weight of a cell whose centre lies d from the keyframe in a window falling from 1 at
// start to 0 at end: the square of a quarter sine, smooth at both ends.
inline double birds_eye_window_weight(double d, double start, double end) {
  const double w = std::clamp((end - d) / (end - start), 0.0, 1.0);
  const double s = std::sin(w * M_PI / 2);
  return s * s;
}
// Whether places of the two configurations compare: the same cell kind, cell size, range,
// weight window and key rings and angles (the configurable fields a signature's meaning and
// width depend on).
inline bool same_layout(const BirdsEyePlaceConfig& a, const BirdsEyePlaceConfig& b) {
  return a.cell == b.cell && a.cell_m == b.cell_m && a.range_m == b.range_m &&
         a.taper_start_m == b.taper_start_m && a.taper_end_m == b.taper_end_m &&
         a.rings == b.rings && a.angles == b.angles;
}
// Whether the two describe alike: the layout and every other field.
inline bool same_description(const BirdsEyePlaceConfig& a, const BirdsEyePlaceConfig& b) {
  return same_layout(a, b) && a.min_height_m == b.min_height_m &&
         a.spectrum_size == b.spectrum_size && a.min_frequency == b.min_frequency &&
         a.max_frequency == b.max_frequency;
}
inline int image_side(const BirdsEyePlaceConfig& config) {
  return std::max(1, static_cast<int>(std::lround(2.0 * config.range_m / config.cell_m)));
}
// A place as a signature row: [image (side^2 values 0..255) | key (rings x angles, -127..127)].
inline int birds_eye_signature_columns(const BirdsEyePlaceConfig& config) {
  const int side = image_side(config);
  return side * side + config.rings * config.angles;
}

struct BirdsEyePlace {
  int side = 0;                     // image cells per side
  std::vector<std::uint8_t> image;  // side x side, row from z, column from x; 255 = the top cell
  std::vector<std::int8_t> key;     // rings x angles, ring means removed, max |value| = 127
  std::size_t bytes() const { return image.size() + key.size(); }
};

// Describes places with one configuration (validated once; per-cell weights computed once).
// Points are in the camera frame of the keyframe (x right, y down, z forward), as three arrays
// of n values. A place without structure gets an all-zero image and key.
class BirdsEyeDescriber {
 public:
  // Throws std::invalid_argument on an invalid config (see validate).
  explicit BirdsEyeDescriber(const BirdsEyePlaceConfig& config = {});
  BirdsEyePlace describe(const float* x, const float* y, const float* z, std::size_t n) const;
  const BirdsEyePlaceConfig& config() const { return config_; }

 private:
  // The tapered cell values before quantisation.
  std::vector<float> image(const float* x, const float* y, const float* z, std::size_t n) const;
  // A density cell's value for a count of points: log(1 + n / 2), from a table for small n.
  float density_value(float count) const {
    const auto n = static_cast<std::size_t>(count);
    return n < density_table_.size() ? density_table_[n] : std::log1p(0.5f * count);
  }

  // A key value: bilinear in the log-magnitude grid between four bins.
  struct KeySample {
    int bin = 0;  // the grid index of the lower-left bin
    float fu = 0, fv = 0;
  };

  BirdsEyePlaceConfig config_;
  int side_ = 0;
  std::vector<float> weights_;  // per cell: 1 within taper_start_m, sin^2 down to 0 at taper_end_m
  std::vector<float> density_table_;  // density_value of 0, 1, 2, ... points
  int band_ = 0;                // the key's samples reach frequencies up to band_ in u and |v|
  int stride_ = 0;              // band_ + 1 frequencies padded to whole vectors
  std::vector<float> row_table_;                // side x 2 stride: cos, then -sin (2 pi c v / N)
  std::vector<float> column_cos_, column_sin_;  // (band + 1) x side: cos, sin (2 pi u r / N)
  std::vector<KeySample> samples_;              // rings x angles
};

Signature birds_eye_signature(const BirdsEyePlace& place);
// Throws std::invalid_argument when the signature is not one row of
// birds_eye_signature_columns(config) whole values in the image's and the key's ranges.
BirdsEyePlace birds_eye_place(const Signature& signature, const BirdsEyePlaceConfig& config);
// The same from the row's values (`columns` of them).
BirdsEyePlace birds_eye_place(const double* values, int columns, const BirdsEyePlaceConfig& config);

// One place (a describer built for it: prefer BirdsEyeDescriber for many places).
BirdsEyePlace describe_birds_eye(const float* x, const float* y, const float* z, std::size_t n,
                                 const BirdsEyePlaceConfig& config = {});

}  // namespace loopscan
