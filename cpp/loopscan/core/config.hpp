#pragma once
// Parameters of every core stage, with the paper's values as defaults.
#include <string>
#include <vector>

#include "loopscan/core/types.hpp"

namespace loopscan {

enum class ScanFilter { Cartesian, Polar };

// The frame a descriptor is computed in (aligned axis 0 = "up", axes 1, 2 horizontal).
// Pca: the paper's: centroid, eigenvectors of the scatter by ascending eigenvalue (which
// axis is up depends on the scan's extent; signs are ambiguous). Camera: centred on the
// keyframe, up = the camera's -y, horizontal = its x and z: rotation is left to the
// descriptor's own search (Scan Context's sector shift); needs a camera that looks roughly
// level (cars, robots; not a hand-held camera). GravityPca: centroid, up = the camera's -y,
// horizontal axes = the 2D principal axes of the horizontal coordinates (descriptors without a
// rotation search: M2DP, DELIGHT). Centroid: as Camera, centred on the horizontal centroid of
// the points within 20 m of the keyframe (lane-independent on a street).
enum class DescriptorFrame { Pca, Camera, GravityPca, Centroid };

// "pca" | "camera" | "gravity-pca" | "centroid"; throws std::invalid_argument otherwise.
DescriptorFrame parse_descriptor_frame(const std::string& name);
std::string descriptor_frame_name(DescriptorFrame frame);

struct ImitationConfig {
  double range_m = 45.0;        // imitated LiDAR range r
  int init_frames = 30;         // keyframes skipped after a reset while points accumulate
  int voxel_divisions_xz = 30;  // Cartesian voxel = r/30 (x, z) ...
  int voxel_divisions_y = 60;   // ... and r/60 (y, the camera's down axis)
  double polar_resolution_deg = 1.0;
  // Two-sided scans (default mode): a keyframe is described once the VO has travelled this far
  // past it, from the points of the keyframes before AND after it, so that what a scan holds no
  // longer depends on the direction of travel. 0: the paper's forward-only scan (the current
  // keyframe, at once). Ignored in reference mode.
  double lookahead_m = 0.0;
  Mode mode = Mode::Default;
};

struct ScanContextConfig {
  int rings = 20;
  int sectors = 60;
  double max_radius_m = 45.0;
  DescriptorFrame frame = DescriptorFrame::Pca;  // reference mode: always Pca
  // Camera frame: centre the descriptor this far right of the keyframe (a diagnostic of
  // lateral sensitivity; a query "from the next lane").
  double lateral_offset_m = 0.0;
  // Lateral versions (camera or centroid frame, default mode): the signature gets one more row
  // per offset, the descriptor centred that many metres further right. Row 0 is the place;
  // a query's distance to a place is, per half, the smallest over its rows, so a revisit one
  // lane over (or a metre aside) matches as if driven at the same spot.
  std::vector<double> lateral_versions_m;
  static constexpr int kMaxLateralVersions = 8;
  // Structure value of a bin: the paper's height range (max - min), or Scan Context's original
  // maximum height above the ground (max + sensor_height_m, at least 0), for real LiDAR scans.
  bool max_height = false;
  double sensor_height_m = 2.0;
  Mode mode = Mode::Default;
};

struct M2dpConfig {
  int azimuth_bins = 16;  // per projection plane
  int radial_bins = 8;
  int plane_azimuths = 4;     // p
  int plane_elevations = 16;  // q
  double max_radius_m = 45.0;
  DescriptorFrame frame = DescriptorFrame::Pca;  // reference mode: always Pca
  Mode mode = Mode::Default;
};

struct DelightConfig {
  double inner_radius_m = 10.0;
  int intensity_bins = 256;
  DescriptorFrame frame = DescriptorFrame::Pca;  // reference mode: always Pca
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
