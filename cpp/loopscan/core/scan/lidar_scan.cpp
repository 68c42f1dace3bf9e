#include "loopscan/core/scan/lidar_scan.hpp"

#include <algorithm>

#include "loopscan/core/scan/camera_points.hpp"
#include "loopscan/core/scan/scan_imitator.hpp"

namespace loopscan {

namespace {

double gray_scale(const Cloud& lidar, const LidarScanOptions& options) {
  if (options.reflectance_scale > 0) return options.reflectance_scale;
  const bool unit =
      std::all_of(lidar.begin(), lidar.end(), [](const PointI& p) { return p.intensity <= 1.0f; });
  return unit ? 255.0 : 1.0;
}

}  // namespace

Cloud lidar_in_range(const Cloud& lidar, double range_m, const LidarScanOptions& options) {
  const double scale = gray_scale(lidar, options), r2 = range_m * range_m;
  Cloud out;
  for (const PointI& p : lidar) {
    const Eigen::Vector3d c(-p.p.y(), -p.p.z(), p.p.x());
    if (c.squaredNorm() < r2)
      out.push_back({c, static_cast<float>(std::clamp(p.intensity * scale, 0.0, 255.0))});
  }
  return out;
}

Cloud lidar_scan_as_imitated(const Cloud& lidar, ScanFilter filter,
                             const ImitationConfig& imitation, const LidarScanOptions& options) {
  validate(imitation);
  const double scale = gray_scale(lidar, options);
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
