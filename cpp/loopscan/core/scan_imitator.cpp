#include "loopscan/core/scan_imitator.hpp"

#include <Eigen/Geometry>

#include "loopscan/core/point_filter.hpp"

namespace loopscan {

ScanImitator::ScanImitator(const ImitationConfig& config) : config_(config) {}

void ScanImitator::reset() {
  local_.clear();
  frames_since_reset_ = 0;
}

bool ScanImitator::add_keyframe(const KeyframePose& keyframe, const IdPoint* points,
                                std::size_t n_points, bool reset_signal, Cloud& in_range) {
  // 1. Reset. The reference heuristic also fires on the first (identity) pose and, wrongly,
  //    whenever the camera passes within 1 m of the VO origin again.
  const bool reference = config_.mode == Mode::Reference;
  if (reference ? keyframe.T_cam_world.col(3).norm() < 1.0 : reset_signal) reset();

  // 2. Accumulate the keyframe's points in the local map.
  local_.reserve(local_.size() + n_points);
  for (std::size_t i = 0; i < n_points; ++i) {
    local_.push_back({points[i].p_world, points[i].intensity});
  }

  // 3. Right after a reset there are too few points for a scan.
  if (frames_since_reset_ < config_.init_frames) {
    ++frames_since_reset_;
    return false;
  }

  // 4. Crop to the range around the camera; points out of range leave the map for good.
  const Eigen::Matrix3d R = keyframe.T_cam_world.leftCols<3>();
  const Eigen::Vector3d t = keyframe.T_cam_world.col(3);
  const double range = config_.range_m, range2 = range * range;
  in_range.resize(local_.size());
  std::size_t kept = 0;
  for (std::size_t i = 0; i < local_.size(); ++i) {
    const PointI q = local_[i];
    const Eigen::Vector3d p_cam = R * q.p + t;
    // Reference: the authors' norm() < r; default: the same test without the square root.
    const bool inside = reference ? p_cam.norm() < range : p_cam.squaredNorm() < range2;
    if (!inside) continue;
    in_range[kept] = {p_cam, q.intensity};
    local_[kept++] = q;
  }
  in_range.resize(kept);
  local_.resize(kept);
  return true;
}

Cloud filter_scan(const Cloud& in_range, ScanFilter filter, const ImitationConfig& config) {
  if (filter == ScanFilter::Cartesian) {
    return cartesian_filter(in_range, config.range_m, config.voxel_divisions_xz,
                            config.voxel_divisions_y, config.mode);
  }
  return polar_filter(in_range, config.polar_resolution_deg, config.mode);
}

}  // namespace loopscan
