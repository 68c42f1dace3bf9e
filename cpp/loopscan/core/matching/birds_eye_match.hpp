#pragma once
// Comparing two bird's-eye places (birds_eye_place.hpp): the keys by one circular correlation
// over their angles (a distance and the yaw modulo pi), then the images by a correlation over
// shifts at that yaw and the yaw plus pi, for the place's metric pose in the query's frame.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "loopscan/core/descriptors/birds_eye_place.hpp"

namespace loopscan {

struct BirdsEyeKeyMatch {
  double distance = 1.0;  // 1 - the best normalised correlation, in [0, 2]; 1 without structure
  double yaw_rad = 0.0;   // in [0, pi): the place turned by it (or it + pi) matches the query
};

// Throws std::invalid_argument when the keys differ in size or do not hold `angles` columns.
BirdsEyeKeyMatch match_keys(const BirdsEyePlace& query, const BirdsEyePlace& place, int angles);

// A key ready for fast matching: per ring, the DFT along the angles (A/2 + 1 terms of a real
// signal, zero-padded to `stride` floats), and the key's norm. match_key_spectra gives
// match_keys' result up to float rounding (a shift whose correlation ties another's within that
// rounding may be chosen instead). Keys of 2 to 720 angles.
inline int key_spectrum_stride(int angles) { return (angles / 2 + 1 + 15) / 16 * 16; }
struct BirdsEyeKeySpectrum {
  int rings = 0, angles = 0, stride = 0;
  std::vector<float> re, im;  // rings x stride
  double norm = 0;
  // re, then im, rounded to the nearest bfloat16 (a float's upper 16 bits; relative error
  // <= 2^-8): half the bytes, what nearest_keys' bound reads.
  std::vector<std::uint16_t> rounded;
};
BirdsEyeKeySpectrum key_spectrum(const BirdsEyePlace& place, int angles);
// A spectrum held elsewhere (a database record); `rounded` may be absent (null).
struct BirdsEyeKeySpectrumView {
  int rings = 0, angles = 0, stride = 0;
  const float* re = nullptr;
  const float* im = nullptr;
  double norm = 0;
  const std::uint16_t* rounded = nullptr;
};
inline BirdsEyeKeySpectrumView view(const BirdsEyeKeySpectrum& s) {
  return {s.rings, s.angles, s.stride, s.re.data(), s.im.data(), s.norm, s.rounded.data()};
}
// A spectrum packed into floats, for keeping many contiguous (a PayloadArena record): the norm,
// then the real and imaginary parts (rings x key_spectrum_stride(angles) each); the bfloat16
// copy, two values to a float, in a record of its own.
inline std::size_t packed_key_spectrum_floats(int rings, int angles) {
  return 1 + 2 * static_cast<std::size_t>(rings) * key_spectrum_stride(angles);
}
inline std::size_t packed_rounded_floats(int rings, int angles) {
  return static_cast<std::size_t>(rings) * key_spectrum_stride(angles);
}
void pack_key_spectrum(const BirdsEyeKeySpectrum& spectrum, float* out);
// The view of a packed spectrum, with its packed bfloat16 copy where given (else null).
inline BirdsEyeKeySpectrumView packed_key_spectrum(const float* packed, int rings, int angles,
                                                   const float* rounded = nullptr) {
  const int stride = key_spectrum_stride(angles);
  const std::size_t floats = static_cast<std::size_t>(rings) * stride;
  return {rings,
          angles,
          stride,
          packed + 1,
          packed + 1 + floats,
          packed[0],
          reinterpret_cast<const std::uint16_t*>(rounded)};
}
// Throws std::invalid_argument when the spectra differ in rings or angles.
BirdsEyeKeyMatch match_key_spectra(const BirdsEyeKeySpectrumView& query,
                                   const BirdsEyeKeySpectrumView& place);
inline BirdsEyeKeyMatch match_key_spectra(const BirdsEyeKeySpectrum& query,
                                          const BirdsEyeKeySpectrum& place) {
  return match_key_spectra(view(query), view(place));
}
// The `count` eligible places of [0, places) nearest to the query by key, as (distance, place)
// in ascending order: what match_key_spectra on every eligible place and sorting the pairs give,
// but a place whose bound on its best shift's correlation (from its cross spectrum, without the
// inverse transform) cannot beat the count-th best so far is never matched in full. The bound
// reads a place's rounded spectrum where its view has one, widened by what the rounding can
// hide (2^-8 of the normalised correlation).
std::vector<std::pair<double, std::size_t>> nearest_keys(
    const BirdsEyeKeySpectrumView& query, std::size_t places,
    const std::function<bool(std::size_t)>& eligible,
    const std::function<BirdsEyeKeySpectrumView(std::size_t)>& spectrum, std::size_t count);

// The place in the query's camera frame on the ground plane: a place point (x, z) lies at
// R(yaw) (x, z) + (x_m, z_m) in the query, R turning x towards z; yaw is about the camera's up
// axis (-y), positive to the left, in (-pi, pi].
struct BirdsEyePose {
  double x_m = 0, z_m = 0, yaw_rad = 0;
  double score = 0;  // the stored images' normalised correlation at the pose, in [0, 1]
  double fit = 0;    // the pose images' (BirdsEyeSearchConfig::pose_window) at the pose
};

struct BirdsEyeSearchConfig {
  double max_shift_m = 12.0;  // searched in x and z around the keyframes' offset of zero
  int yaw_steps = 0;          // extra yaws each side of the key's, one key angle apart
  // The shifts are first searched on cells merged coarse_cells x coarse_cells, and the
  // refined_peaks best of those peaks (over all yaws) then at full resolution around them;
  // coarse_cells = 1 searches every shift at full resolution.
  int coarse_cells = 2;
  int refined_peaks = 5;
  // With it, the pose is searched on both images weighed from 1 at pose_window_start_m to 0
  // at pose_window_end_m from their keyframes and scored on the images as stored: near
  // structure to fix the pose along a street, all of it as evidence (for flat stored windows,
  // BirdsEyePlaceConfig::taper_start_m near taper_end_m). A window that starts at or beyond
  // the stored window's end (the default) weighs nothing: pose and score on the stored images.
  double pose_window_start_m = 30.0;
  double pose_window_end_m = 32.0;
  // Places ranked by key whose images are searched (a difference-matrix row's or a database
  // query's finalists): the image search costs ~200x a key match. 10 finalists recognise a
  // little more (city AUC +0.03) for twice the query's cost.
  int finalists = 5;
};

// Throws std::invalid_argument when a search cannot run on places of `config`.
void validate(const BirdsEyeSearchConfig& search, const BirdsEyePlaceConfig& config);

// The bird's-eye place distance: 1 - the image score at the place's best pose, in [0, 1].
inline double birds_eye_distance(const BirdsEyePose& pose) { return 1.0 - pose.score; }

// The best pose over the key's yaw, the yaw plus pi (and yaw_steps around each) and the
// whole-cell shifts within max_shift_m (all of them, or coarse to fine), refined to a fraction
// of a cell; score 0 at (0, 0, the key's yaw) when no shift correlates at all. Throws
// std::invalid_argument on images of another size than config describes or an invalid search.
BirdsEyePose birds_eye_pose(const BirdsEyePlace& query, const BirdsEyePlace& place,
                            double key_yaw_rad, const BirdsEyePlaceConfig& config,
                            const BirdsEyeSearchConfig& search = {});

// birds_eye_pose for one query and many places: the query's padded images are built once.
class BirdsEyeImageSearch {
 public:
  // Throws std::invalid_argument as birds_eye_pose does.
  BirdsEyeImageSearch(const BirdsEyePlace& query, const BirdsEyePlaceConfig& config,
                      const BirdsEyeSearchConfig& search = {});
  BirdsEyePose pose(const BirdsEyePlace& place, double key_yaw_rad) const;

 private:
  struct Prepared;
  std::shared_ptr<const Prepared> prepared_;
};

// The normalised correlation of the query image with the place image turned by yaw_rad, at
// every whole-cell shift (dx, dz) in [-max_cells, max_cells]^2: row-major from (-max, -max),
// column = dx. On the pose images, what birds_eye_pose maximises; on the stored ones, its score.
std::vector<double> birds_eye_correlation(const BirdsEyePlace& query, const BirdsEyePlace& place,
                                          double yaw_rad, const BirdsEyePlaceConfig& config,
                                          int max_cells);

// The correlation birds_eye_pose maximises, laid out as birds_eye_correlation's: the query
// image and the turned place image, each cell weighed by its centre's weight in the search's
// pose window (the weight turns with the image: it depends only on the distance from the
// keyframe).
std::vector<double> birds_eye_pose_correlation(const BirdsEyePlace& query,
                                               const BirdsEyePlace& place, double yaw_rad,
                                               const BirdsEyePlaceConfig& config,
                                               const BirdsEyeSearchConfig& search, int max_cells);

}  // namespace loopscan
