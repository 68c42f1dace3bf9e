#pragma once
// A real LiDAR scan as a place: the sensor's points (x forward, y left, z up) turned into the
// camera convention of imitated scans (x right, y down, z forward), cropped to the range and
// filtered like an imitated scan, so every descriptor, the database and the loop closer take it
// as they take a VO keyframe.
#include "loopscan/core/config.hpp"

namespace loopscan {

struct LidarScanOptions {
  // Intensity = reflectance * scale; 0: 255 when every reflectance is <= 1 (KITTI's [0, 1]),
  // else 1 (sensors that already write 0..255).
  double reflectance_scale = 0;
};

// The points within `range_m`, in the camera convention, gray = reflectance * scale, unfiltered
// (what the loop closer aligns: LoopCloser::add_scan).
Cloud lidar_in_range(const Cloud& lidar, double range_m, const LidarScanOptions& options = {});

// Throws std::invalid_argument on an invalid imitation config.
Cloud lidar_scan_as_imitated(const Cloud& lidar, ScanFilter filter,
                             const ImitationConfig& imitation,
                             const LidarScanOptions& options = {});

}  // namespace loopscan
