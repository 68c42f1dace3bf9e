#include "loopscan/core/scan/scan_imitator.hpp"

#include <Eigen/Geometry>

#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <string>

#include "loopscan/core/scan/point_filter.hpp"

namespace loopscan {

namespace {

// c = R w + t for every point; restrict-qualified so that the loop vectorises.
void transform_points(const float (&R)[9], const float (&t)[3], const float* __restrict wx,
                      const float* __restrict wy, const float* __restrict wz, std::size_t n,
                      float* __restrict cx, float* __restrict cy, float* __restrict cz) {
  for (std::size_t i = 0; i < n; ++i) {
    cx[i] = R[0] * wx[i] + R[1] * wy[i] + R[2] * wz[i] + t[0];
    cy[i] = R[3] * wx[i] + R[4] * wy[i] + R[5] * wz[i] + t[1];
    cz[i] = R[6] * wx[i] + R[7] * wy[i] + R[8] * wz[i] + t[2];
  }
}

// Finite and representable in single precision (the default mode's local map).
bool usable(double v) { return std::abs(v) <= FLT_MAX; }

bool usable(const IdPoint& q) {
  return usable(q.p_world.x()) && usable(q.p_world.y()) && usable(q.p_world.z()) &&
         std::isfinite(q.intensity);
}

}  // namespace

ScanImitator::ScanImitator(const ImitationConfig& config) : config_(config) { validate(config); }

void ScanImitator::reset() {
  local_.clear();
  world_.resize(0);
  frames_since_reset_ = 0;
  pending_.clear();
  path_m_ = 0;
  has_centre_ = false;
}

void ScanImitator::check_pose(const KeyframePose& keyframe) const {
  for (int k = 0; k < 12; ++k) {
    if (!usable(keyframe.T_cam_world(k / 4, k % 4))) {
      throw std::invalid_argument("ScanImitator: keyframe " + std::to_string(keyframe.id) +
                                  " has a non-finite pose");
    }
  }
}

void ScanImitator::append_points(const IdPoint* points, std::size_t n_points) {
  // Points with NaN or infinite values (which no crop would keep) are left out and counted.
  if (config_.mode == Mode::Reference) {
    for (std::size_t i = 0; i < n_points; ++i) {
      if (!usable(points[i])) {
        ++unusable_points_;
        continue;
      }
      local_.push_back({points[i].p_world, points[i].intensity});
    }
    return;
  }
  for (std::size_t i = 0; i < n_points; ++i) {
    if (!usable(points[i])) {
      ++unusable_points_;
      continue;
    }
    world_.x.push_back(static_cast<float>(points[i].p_world.x()));
    world_.y.push_back(static_cast<float>(points[i].p_world.y()));
    world_.z.push_back(static_cast<float>(points[i].p_world.z()));
    world_.gray.push_back(points[i].intensity);
  }
}

bool ScanImitator::accumulate(const KeyframePose& keyframe, const IdPoint* points,
                              std::size_t n_points, bool reset_signal) {
  // 1. Reset. The reference heuristic also fires on the first (identity) pose and, wrongly,
  //    whenever the camera passes within 1 m of the VO origin again.
  const bool reference = config_.mode == Mode::Reference;
  check_pose(keyframe);
  if (reference ? keyframe.T_cam_world.col(3).norm() < 1.0 : reset_signal) reset();
  // 2. Accumulate the keyframe's points in the local map.
  append_points(points, n_points);

  // 3. Right after a reset there are too few points for a scan.
  if (frames_since_reset_ < config_.init_frames) {
    ++frames_since_reset_;
    return false;
  }
  return true;
}

bool ScanImitator::add_keyframe(const KeyframePose& keyframe, const IdPoint* points,
                                std::size_t n_points, bool reset_signal, Cloud& in_range) {
  if (!accumulate(keyframe, points, n_points, reset_signal)) return false;
  if (config_.mode == Mode::Reference) {
    crop_reference(keyframe, in_range);
    return true;
  }
  thread_local CameraPoints fast;
  crop_fast(keyframe, fast);
  in_range = to_cloud(fast);
  return true;
}

bool ScanImitator::add_keyframe(const KeyframePose& keyframe, const IdPoint* points,
                                std::size_t n_points, bool reset_signal, CameraPoints& in_range) {
  if (!accumulate(keyframe, points, n_points, reset_signal)) return false;
  if (config_.mode == Mode::Default) {
    crop_fast(keyframe, in_range);
    return true;
  }
  Cloud cloud;
  crop_reference(keyframe, cloud);
  in_range = to_camera_points(cloud);
  return true;
}

void ScanImitator::crop_reference(const KeyframePose& keyframe, Cloud& in_range) {
  // 4. Crop to the range around the camera; points out of range leave the map for good.
  const Eigen::Matrix3d R = keyframe.T_cam_world.leftCols<3>();
  const Eigen::Vector3d t = keyframe.T_cam_world.col(3);
  const double range = config_.range_m;
  in_range.resize(local_.size());
  std::size_t kept = 0;
  for (std::size_t i = 0; i < local_.size(); ++i) {
    const PointI q = local_[i];
    const Eigen::Vector3d p_cam = R * q.p + t;
    if (!(p_cam.norm() < range)) continue;  // the authors' test, with the square root
    in_range[kept] = {p_cam, q.intensity};
    local_[kept++] = q;
  }
  in_range.resize(kept);
  local_.resize(kept);
}

void ScanImitator::crop_fast(const KeyframePose& keyframe, CameraPoints& in_range,
                             bool forget_out_of_range) {
  // 4. Crop in single precision: transform every point (a loop the compiler vectorises), then
  //    compact the camera-frame output (and the world map, when out-of-range points leave it).
  float R[9], t[3];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R[3 * r + c] = static_cast<float>(keyframe.T_cam_world(r, c));
    t[r] = static_cast<float>(keyframe.T_cam_world(r, 3));
  }
  const float range2 = static_cast<float>(config_.range_m * config_.range_m);
  const std::size_t n = world_.size();
  in_range.resize(n);
  transform_points(R, t, world_.x.data(), world_.y.data(), world_.z.data(), n, in_range.x.data(),
                   in_range.y.data(), in_range.z.data());
  float *cx = in_range.x.data(), *cy = in_range.y.data(), *cz = in_range.z.data();
  const float *wx = world_.x.data(), *wy = world_.y.data(), *wz = world_.z.data();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool inside = cx[i] * cx[i] + cy[i] * cy[i] + cz[i] * cz[i] < range2;
    cx[kept] = cx[i];
    cy[kept] = cy[i];
    cz[kept] = cz[i];
    in_range.gray[kept] = world_.gray[i];
    if (forget_out_of_range) {  // loop-invariant: the compiler unswitches it
      world_.x[kept] = wx[i];
      world_.y[kept] = wy[i];
      world_.z[kept] = wz[i];
      world_.gray[kept] = world_.gray[i];
    }
    kept += inside;  // branch-free compaction: always write, advance only when kept
  }
  in_range.resize(kept);
  if (forget_out_of_range) world_.resize(kept);
}

Cloud filter_scan(const Cloud& in_range, ScanFilter filter, const ImitationConfig& config) {
  if (filter == ScanFilter::Cartesian) {
    return cartesian_filter(in_range, config.range_m, config.voxel_divisions_xz,
                            config.voxel_divisions_y, config.mode);
  }
  return polar_filter(in_range, config.polar_resolution_deg, config.mode);
}

bool ScanImitator::next_scan(const KeyframePose& keyframe, const IdPoint* points,
                             std::size_t n_points, bool reset, ScanFilter filter, Cloud& scan,
                             std::size_t* in_range_count) {
  if (config_.mode == Mode::Reference) {
    if (!add_keyframe(keyframe, points, n_points, reset, in_range_)) return false;
    scan = filter_scan(in_range_, filter, config_);
    if (in_range_count) *in_range_count = in_range_.size();
  } else {
    if (!add_keyframe(keyframe, points, n_points, reset, in_range_fast_)) return false;
    scan = filter_camera_points(in_range_fast_, filter, config_);
    if (in_range_count) *in_range_count = in_range_fast_.size();
  }
  return true;
}

void ScanImitator::last_in_range(std::vector<Eigen::Vector3f>& out) const {
  out.clear();
  if (config_.mode == Mode::Reference) {
    out.reserve(in_range_.size());
    for (const PointI& p : in_range_) out.push_back(p.p.cast<float>());
  } else {
    const CameraPoints& c = in_range_fast_;
    out.reserve(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) out.emplace_back(c.x[i], c.y[i], c.z[i]);
  }
}

}  // namespace loopscan
