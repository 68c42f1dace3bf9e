#include "loopscan/eval/loop_metrics.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace loopscan::eval {

RelativeError relative_pose_error(const std::vector<Eigen::Isometry3d>& gt,
                                  const std::vector<Eigen::Isometry3d>& est, double delta_m) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("relative pose error: " + std::to_string(est.size()) +
                                " estimated poses for " + std::to_string(gt.size()));
  }
  if (!(delta_m > 0) || !std::isfinite(delta_m)) {
    throw std::invalid_argument("relative pose error: delta must be finite and > 0");
  }
  RelativeError r;
  double t2 = 0, r2 = 0, path = 0;
  std::size_t i = 0;
  bool started = false;  // evo's first pair starts at the first crossing, not at pose 0
  for (std::size_t j = 1; j < est.size(); ++j) {
    path += (est[j].translation() - est[j - 1].translation()).norm();
    if (path < delta_m) continue;
    path = 0;
    if (started) {
      const Eigen::Isometry3d e =
          (gt[i].inverse() * gt[j]).inverse() * (est[i].inverse() * est[j]);
      t2 += e.translation().squaredNorm();
      const double angle = Eigen::AngleAxisd(e.rotation()).angle() * 180.0 / M_PI;
      r2 += angle * angle;
      ++r.pairs;
    }
    started = true;
    i = j;
  }
  if (r.pairs > 0) {
    r.translation_rmse_m = std::sqrt(t2 / r.pairs);
    r.rotation_rmse_deg = std::sqrt(r2 / r.pairs);
  }
  return r;
}

Eigen::Isometry3d rigid_alignment(const std::vector<Eigen::Vector3d>& gt,
                                  const std::vector<Eigen::Vector3d>& est) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("alignment: " + std::to_string(est.size()) +
                                " estimated positions for " + std::to_string(gt.size()));
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (gt.size() < 3) return T;
  Eigen::Matrix3Xd src(3, est.size()), dst(3, gt.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {
    src.col(Eigen::Index(i)) = est[i];
    dst.col(Eigen::Index(i)) = gt[i];
  }
  T.matrix() = Eigen::umeyama(src, dst, false);
  return T;
}

double aligned_rmse(const std::vector<Eigen::Vector3d>& gt,
                    const std::vector<Eigen::Vector3d>& est) {
  const Eigen::Isometry3d T = rigid_alignment(gt, est);
  double sum = 0;
  for (std::size_t i = 0; i < gt.size(); ++i) sum += (T * est[i] - gt[i]).squaredNorm();
  return gt.empty() ? 0.0 : std::sqrt(sum / double(gt.size()));
}

LoopTruth loop_truth(const Eigen::Isometry3d& T_query_match, const Eigen::Isometry3d& gt_query,
                     const Eigen::Isometry3d& gt_match, double true_within_m) {
  LoopTruth t;
  const Eigen::Isometry3d gt_rel = gt_query.inverse() * gt_match;
  t.gt_distance_m = gt_rel.translation().norm();
  t.is_true = t.gt_distance_m <= true_within_m;
  const Eigen::Isometry3d e = gt_rel.inverse() * T_query_match;
  t.translation_error_m = e.translation().norm();
  t.rotation_error_deg = Eigen::AngleAxisd(e.rotation()).angle() * 180.0 / M_PI;
  return t;
}

}  // namespace loopscan::eval
