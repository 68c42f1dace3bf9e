#include "loopscan/core/config.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace loopscan {
namespace {

constexpr double kMaxRangeM = 1000.0;          // no LiDAR or stereo VO sees farther
constexpr double kMaxCells = double(1 << 26);  // dense per-cell tables stay below ~0.5 GB

void need(bool ok, const char* config, const std::string& what) {
  if (!ok) throw std::invalid_argument(std::string(config) + ": " + what);
}

bool in(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

std::string got(double v) { return " (got " + std::to_string(v) + ")"; }

}  // namespace

DescriptorFrame parse_descriptor_frame(const std::string& name) {
  if (name == "pca") return DescriptorFrame::Pca;
  if (name == "camera") return DescriptorFrame::Camera;
  if (name == "gravity-pca") return DescriptorFrame::GravityPca;
  if (name == "centroid") return DescriptorFrame::Centroid;
  throw std::invalid_argument("unknown descriptor frame '" + name +
                              "' (expected pca, camera, gravity-pca or centroid)");
}

std::string descriptor_frame_name(DescriptorFrame frame) {
  switch (frame) {
    case DescriptorFrame::Camera:
      return "camera";
    case DescriptorFrame::GravityPca:
      return "gravity-pca";
    case DescriptorFrame::Centroid:
      return "centroid";
    case DescriptorFrame::Pca:
      break;
  }
  return "pca";
}

void validate(const ImitationConfig& c) {
  const char* name = "ImitationConfig";
  need(in(c.range_m, 0.1, kMaxRangeM), name,
       "range_m must be a finite number in [0.1, 1000] m" + got(c.range_m));
  need(in(c.lookahead_m, 0.0, kMaxRangeM), name,
       "lookahead_m must be a finite number in [0, 1000] m" + got(c.lookahead_m));
  need(c.init_frames >= 0 && c.init_frames <= 100000, name, "init_frames must be in [0, 100000]");
  need(c.voxel_divisions_xz >= 1 && c.voxel_divisions_y >= 1, name, "voxel divisions must be >= 1");
  // Cartesian cells: (2 d_xz + 1)^2 (2 d_y + 1); polar cells: (360/res + 1)(180/res + 1).
  const double xz = 2.0 * c.voxel_divisions_xz + 1, y = 2.0 * c.voxel_divisions_y + 1;
  need(xz * xz * y <= kMaxCells, name,
       "voxel divisions give more than 2^26 cells (" + std::to_string(c.voxel_divisions_xz) +
           " x " + std::to_string(c.voxel_divisions_y) + ")");
  need(in(c.polar_resolution_deg, 0.05, 90.0), name,
       "polar_resolution_deg must be in [0.05, 90]" + got(c.polar_resolution_deg));
}

void validate(const ScanContextConfig& c) {
  const char* name = "ScanContextConfig";
  need(c.rings >= 1 && c.rings <= 1000, name, "rings must be in [1, 1000]");
  need(c.sectors >= 1 && c.sectors <= 3600, name, "sectors must be in [1, 3600]");
  need(in(c.max_radius_m, 0.1, kMaxRangeM), name,
       "max_radius_m must be a finite number in [0.1, 1000] m" + got(c.max_radius_m));
  need(in(c.lateral_offset_m, -100.0, 100.0), name,
       "lateral_offset_m must be a finite number in [-100, 100] m" + got(c.lateral_offset_m));
  need(in(c.sensor_height_m, -100.0, 100.0), name,
       "sensor_height_m must be a finite number in [-100, 100] m" + got(c.sensor_height_m));
  need(c.lateral_versions_m.size() <= ScanContextConfig::kMaxLateralVersions, name,
       "lateral_versions_m holds at most 8 offsets");
  for (double v : c.lateral_versions_m) {
    need(in(v, -100.0, 100.0), name,
         "lateral_versions_m must hold finite numbers in [-100, 100] m" + got(v));
  }
  need(c.lateral_versions_m.empty() ||
           (c.mode == Mode::Default &&
            (c.frame == DescriptorFrame::Camera || c.frame == DescriptorFrame::Centroid)),
       name, "lateral_versions_m needs the default mode and the camera or centroid frame");
}

void validate(const M2dpConfig& c) {
  const char* name = "M2dpConfig";
  need(c.azimuth_bins >= 1 && c.azimuth_bins <= 1000 && c.radial_bins >= 1 && c.radial_bins <= 1000,
       name, "azimuth_bins and radial_bins must be in [1, 1000]");
  need(c.plane_azimuths >= 1 && c.plane_azimuths <= 1000 && c.plane_elevations >= 1 &&
           c.plane_elevations <= 1000,
       name, "plane_azimuths and plane_elevations must be in [1, 1000]");
  need(in(c.max_radius_m, 0.1, kMaxRangeM), name,
       "max_radius_m must be a finite number in [0.1, 1000] m" + got(c.max_radius_m));
}

void validate(const DelightConfig& c) {
  const char* name = "DelightConfig";
  need(in(c.inner_radius_m, 0.0, kMaxRangeM), name,
       "inner_radius_m must be a finite number in [0, 1000] m" + got(c.inner_radius_m));
  need(c.intensity_bins >= 1 && c.intensity_bins <= 65536, name,
       "intensity_bins must be in [1, 65536]");
}

}  // namespace loopscan
