#pragma once
// An imitated scan before filtering, in single precision and structure-of-arrays layout: the
// default-mode fast path (vectorised cell keys). Camera frame, points within range.
#include <vector>

#include "loopscan/core/config.hpp"

namespace loopscan {

struct CameraPoints {
  std::vector<float> x, y, z, gray;
  std::size_t size() const { return x.size(); }
  void resize(std::size_t n) {
    x.resize(n);
    y.resize(n);
    z.resize(n);
    gray.resize(n);
  }
};

// Conversions between the two layouts (double <-> float coordinates).
CameraPoints to_camera_points(const Cloud& cloud);
Cloud to_cloud(const CameraPoints& points);

// Default-mode filter on the float SoA scan: the same cells and keep rules as
// cartesian_filter / polar_filter (keys from the float coordinates, exact at every boundary),
// output ordered by cell. Points outside the range cube (Cartesian) or with NaN coordinates
// (both) are dropped. Throws std::invalid_argument on an invalid config.
Cloud filter_camera_points(const CameraPoints& points, ScanFilter filter,
                           const ImitationConfig& config);

}  // namespace loopscan
