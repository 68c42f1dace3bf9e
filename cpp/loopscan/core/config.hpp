#pragma once
// Parameters of every core stage, with the paper's values as defaults.
#include "loopscan/core/types.hpp"

namespace loopscan {

enum class ScanFilter { Cartesian, Polar };

struct ImitationConfig {
  double range_m = 45.0;        // imitated LiDAR range r
  int init_frames = 30;         // keyframes skipped after a reset while points accumulate
  int voxel_divisions_xz = 30;  // Cartesian voxel = r/30 (x, z) ...
  int voxel_divisions_y = 60;   // ... and r/60 (y, the camera's down axis)
  double polar_resolution_deg = 1.0;
  Mode mode = Mode::Default;
};

struct ScanContextConfig {
  int rings = 20;
  int sectors = 60;
  double max_radius_m = 45.0;
  Mode mode = Mode::Default;
};

struct M2dpConfig {
  int azimuth_bins = 16;  // per projection plane
  int radial_bins = 8;
  int plane_azimuths = 4;     // p
  int plane_elevations = 16;  // q
  double max_radius_m = 45.0;
  Mode mode = Mode::Default;
};

struct DelightConfig {
  double inner_radius_m = 10.0;
  int intensity_bins = 256;
  Mode mode = Mode::Default;
};

// Each throws std::invalid_argument naming the first field that is out of its range: NaN and
// infinite values, sizes whose tables would not fit in memory (cell counts above 2^26),
// ranges beyond 1 km. Every stage that takes a config checks it on construction.
void validate(const ImitationConfig& config);
void validate(const ScanContextConfig& config);
void validate(const M2dpConfig& config);
void validate(const DelightConfig& config);

// The filter each descriptor uses in the paper.
inline ScanFilter filter_for(Method method) {
  return method == Method::ScanContext ? ScanFilter::Cartesian : ScanFilter::Polar;
}

}  // namespace loopscan
