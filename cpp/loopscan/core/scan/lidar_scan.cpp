#include "loopscan/core/scan/lidar_scan.hpp"

#include <algorithm>

#include "loopscan/core/scan/camera_points.hpp"
#include "loopscan/core/scan/scan_imitator.hpp"

namespace loopscan {

Cloud lidar_scan_as_imitated(const Cloud& lidar, ScanFilter filter,
                             const ImitationConfig& imitation, const LidarScanOptions& options) {
  validate(imitation);
  double scale = options.reflectance_scale;
  if (scale <= 0) {
    const bool unit = std::all_of(lidar.begin(), lidar.end(),
                                  [](const PointI& p) { return p.intensity <= 1.0f; });
    scale = unit ? 255.0 : 1.0;
  }
  const double r2 = imitation.range_m * imitation.range_m;
  // Default mode: straight into the float SoA layout of the fast filter (one pass, no copy).
  CameraPoints fast;
  Cloud in_range;
  const bool reference = imitation.mode == Mode::Reference;
  (reference ? in_range.reserve(lidar.size()) : fast.x.reserve(lidar.size()));
  for (const PointI& p : lidar) {
    const double x = -p.p.y(), y = -p.p.z(), z = p.p.x();
    if (x * x + y * y + z * z >= r2) continue;
    const float gray = static_cast<float>(std::clamp(p.intensity * scale, 0.0, 255.0));
    if (reference) {
      in_range.push_back({{x, y, z}, gray});
    } else {
      fast.x.push_back(static_cast<float>(x));
      fast.y.push_back(static_cast<float>(y));
      fast.z.push_back(static_cast<float>(z));
      fast.gray.push_back(gray);
    }
  }
  return reference ? filter_scan(in_range, filter, imitation)
                   : filter_camera_points(fast, filter, imitation);
}

}  // namespace loopscan
