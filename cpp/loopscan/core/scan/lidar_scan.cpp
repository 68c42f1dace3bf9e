#include "loopscan/core/scan/lidar_scan.hpp"

#include <algorithm>

#include "loopscan/core/scan/camera_points.hpp"
#include "loopscan/core/scan/scan_imitator.hpp"

namespace loopscan {

namespace {

// Calls emit(x, y, z, gray) for each point within `range_m`, in the camera convention
// (x right = -y_lidar, y down = -z_lidar, z forward = x_lidar), gray = reflectance * scale.
template <typename Emit>
void for_each_in_range(const Cloud& lidar, double range_m, const LidarScanOptions& options,
                       Emit emit) {
  double scale = options.reflectance_scale;
  if (scale <= 0) {
    const bool unit = std::all_of(lidar.begin(), lidar.end(),
                                  [](const PointI& p) { return p.intensity <= 1.0f; });
    scale = unit ? 255.0 : 1.0;
  }
  const double r2 = range_m * range_m;
  for (const PointI& p : lidar) {
    const double x = -p.p.y(), y = -p.p.z(), z = p.p.x();
    if (x * x + y * y + z * z < r2)
      emit(x, y, z, static_cast<float>(std::clamp(p.intensity * scale, 0.0, 255.0)));
  }
}

}  // namespace

Cloud lidar_in_range(const Cloud& lidar, double range_m, const LidarScanOptions& options) {
  Cloud out;
  for_each_in_range(lidar, range_m, options, [&](double x, double y, double z, float gray) {
    out.push_back({{x, y, z}, gray});
  });
  return out;
}

Cloud lidar_scan_as_imitated(const Cloud& lidar, ScanFilter filter,
                             const ImitationConfig& imitation, const LidarScanOptions& options) {
  validate(imitation);
  if (imitation.mode == Mode::Reference)
    return filter_scan(lidar_in_range(lidar, imitation.range_m, options), filter, imitation);
  // Default mode: straight into the float SoA layout of the fast filter (no Cloud copy).
  CameraPoints fast;
  for (std::vector<float>* v : {&fast.x, &fast.y, &fast.z, &fast.gray}) v->reserve(lidar.size());
  for_each_in_range(lidar, imitation.range_m, options,
                    [&](double x, double y, double z, float gray) {
                      fast.x.push_back(static_cast<float>(x));
                      fast.y.push_back(static_cast<float>(y));
                      fast.z.push_back(static_cast<float>(z));
                      fast.gray.push_back(gray);
                    });
  return filter_camera_points(fast, filter, imitation);
}

}  // namespace loopscan
