// The streaming step of ScanImitator, and its two-sided scans: a keyframe waits until the VO is
// lookahead_m past it, then its scan is cropped from a map that holds the points of the
// keyframes before and after it.
#include <cmath>
#include <utility>

#include "loopscan/core/scan/scan_imitator.hpp"

namespace loopscan {
namespace {

struct FloatPose {
  float R[9], t[3];
  explicit FloatPose(const Pose3x4& T) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) R[3 * r + c] = static_cast<float>(T(r, c));
      t[r] = static_cast<float>(T(r, 3));
    }
  }
  float squared_range(float x, float y, float z) const {
    const float cx = R[0] * x + R[1] * y + R[2] * z + t[0];
    const float cy = R[3] * x + R[4] * y + R[5] * z + t[1];
    const float cz = R[6] * x + R[7] * y + R[8] * z + t[2];
    return cx * cx + cy * cy + cz * cz;
  }
};

}  // namespace

void ScanImitator::push(const KeyframePose& keyframe, const IdPoint* points, std::size_t n_points,
                        bool reset, ScanFilter filter, std::vector<ReadyScan>& ready) {
  if (!two_sided()) {  // forward-only: this keyframe's scan, as next_scan gives it
    ReadyScan r;
    if (!next_scan(keyframe, points, n_points, reset, filter, r.scan)) return;
    r.keyframe = keyframe;
    r.in_range = config_.mode == Mode::Reference ? to_camera_points(in_range_) : in_range_fast_;
    ready.push_back(std::move(r));
    return;
  }
  check_pose(keyframe);
  if (reset) {  // the waiting keyframes' map ends here: describe them with what it holds
    finish(filter, ready);
    this->reset();
  }
  append_points(points, n_points);
  const Eigen::Vector3d centre = camera_centre(keyframe.T_cam_world);
  if (has_centre_) path_m_ += (centre - last_centre_).norm();
  last_centre_ = centre;
  has_centre_ = true;
  pending_.push_back({keyframe, path_m_});
  while (!pending_.empty() && path_m_ - pending_.front().path_m >= config_.lookahead_m) {
    emit_two_sided(pending_.front(), filter, ready);
    pending_.pop_front();
  }
  prune_two_sided(keyframe);
}

void ScanImitator::finish(ScanFilter filter, std::vector<ReadyScan>& ready) {
  for (const Pending& p : pending_) emit_two_sided(p, filter, ready);
  pending_.clear();
}

void ScanImitator::emit_two_sided(const Pending& p, ScanFilter filter,
                                  std::vector<ReadyScan>& ready) {
  ReadyScan r;
  r.keyframe = p.keyframe;
  crop_fast(p.keyframe, r.in_range, false);
  r.scan = filter_camera_points(r.in_range, filter, config_);
  ready.push_back(std::move(r));
}

void ScanImitator::prune_two_sided(const KeyframePose& newest) {
  // A point out of range of both ends of the waiting stretch is out of range of the keyframes in
  // between too (up to the chord of a curve): it leaves the map for good, like the paper's crop.
  const FloatPose a(newest.T_cam_world);
  const FloatPose b(pending_.empty() ? newest.T_cam_world : pending_.front().keyframe.T_cam_world);
  const float range2 = static_cast<float>(config_.range_m * config_.range_m);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < world_.size(); ++i) {
    const float x = world_.x[i], y = world_.y[i], z = world_.z[i];
    world_.x[kept] = x;
    world_.y[kept] = y;
    world_.z[kept] = z;
    world_.gray[kept] = world_.gray[i];
    kept += a.squared_range(x, y, z) < range2 || b.squared_range(x, y, z) < range2;
  }
  world_.resize(kept);
}

}  // namespace loopscan
