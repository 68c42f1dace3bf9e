#include "loopscan/eval/odometry_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace loopscan::eval {
namespace {

double rotation_angle(const Eigen::Matrix3d& R) {
  return std::acos(std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0));
}

void check_sizes(const std::vector<Eigen::Isometry3d>& gt,
                 const std::vector<Eigen::Isometry3d>& estimate) {
  if (gt.size() != estimate.size())
    throw std::invalid_argument("odometry metrics: " + std::to_string(estimate.size()) +
                                " estimated poses for " + std::to_string(gt.size()) +
                                " ground-truth poses");
}

}  // namespace

std::vector<double> path_distances(const std::vector<Eigen::Isometry3d>& T) {
  std::vector<double> d(T.size(), 0.0);
  for (std::size_t i = 1; i < T.size(); ++i)
    d[i] = d[i - 1] + (T[i].translation() - T[i - 1].translation()).norm();
  return d;
}

std::vector<SegmentError> segment_errors(const std::vector<Eigen::Isometry3d>& gt,
                                         const std::vector<Eigen::Isometry3d>& est,
                                         const OdometryOptions& options) {
  check_sizes(gt, est);
  const std::vector<double> dist = path_distances(gt);
  std::vector<SegmentError> out;
  const int n = static_cast<int>(gt.size());
  for (int first = 0; first < n; first += std::max(1, options.step_frames)) {
    for (double length : options.segment_lengths_m) {
      // First frame farther along the path than `length` from `first`.
      const auto it = std::upper_bound(dist.begin() + first, dist.end(), dist[first] + length);
      if (it == dist.end()) continue;
      const int last = static_cast<int>(it - dist.begin());
      const Eigen::Isometry3d gt_delta = gt[first].inverse() * gt[last];
      const Eigen::Isometry3d est_delta = est[first].inverse() * est[last];
      const Eigen::Isometry3d error = est_delta.inverse() * gt_delta;
      out.push_back({first, last, length, error.translation().norm() / length,
                     rotation_angle(error.linear()) / length});
    }
  }
  return out;
}

double ate_rmse(const std::vector<Eigen::Isometry3d>& gt,
                const std::vector<Eigen::Isometry3d>& est) {
  check_sizes(gt, est);
  if (gt.empty()) return 0.0;
  Eigen::Matrix3Xd src(3, est.size()), dst(3, gt.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {
    src.col(static_cast<Eigen::Index>(i)) = est[i].translation();
    dst.col(static_cast<Eigen::Index>(i)) = gt[i].translation();
  }
  const Eigen::Matrix4d A = Eigen::umeyama(src, dst, false);
  const Eigen::Matrix3Xd aligned = (A.topLeftCorner<3, 3>() * src).colwise() + A.topRightCorner<3, 1>();
  return std::sqrt((aligned - dst).colwise().squaredNorm().mean());
}

Sim3Alignment sim3_alignment(const std::vector<Eigen::Vector3d>& gt,
                             const std::vector<Eigen::Vector3d>& est) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("sim3 alignment: " + std::to_string(est.size()) +
                                " estimated positions for " + std::to_string(gt.size()) +
                                " ground-truth ones");
  }
  Sim3Alignment out;
  if (gt.empty()) return out;
  Eigen::Matrix3Xd src(3, est.size()), dst(3, gt.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {
    src.col(static_cast<Eigen::Index>(i)) = est[i];
    dst.col(static_cast<Eigen::Index>(i)) = gt[i];
  }
  const bool still = (src.colwise() - src.rowwise().mean()).squaredNorm() == 0;
  const Eigen::Matrix4d A = Eigen::umeyama(src, dst, !still);  // no scale to estimate if still
  const Eigen::Matrix3d sR = A.topLeftCorner<3, 3>();
  out.scale = still ? 1.0 : std::cbrt(sR.determinant());
  const Eigen::Matrix3Xd aligned = (sR * src).colwise() + A.topRightCorner<3, 1>();
  out.rmse_m = std::sqrt((aligned - dst).colwise().squaredNorm().mean());
  return out;
}

Sim3Alignment sim3_alignment(const std::vector<Eigen::Isometry3d>& gt,
                             const std::vector<Eigen::Isometry3d>& est) {
  check_sizes(gt, est);
  std::vector<Eigen::Vector3d> g, e;
  for (const Eigen::Isometry3d& T : gt) g.push_back(T.translation());
  for (const Eigen::Isometry3d& T : est) e.push_back(T.translation());
  return sim3_alignment(g, e);
}

OdometryMetrics odometry_metrics(const std::vector<Eigen::Isometry3d>& gt,
                                 const std::vector<Eigen::Isometry3d>& est,
                                 const OdometryOptions& options) {
  check_sizes(gt, est);
  if (gt.size() < 2) throw std::invalid_argument("odometry metrics: need at least 2 poses");
  OdometryMetrics m;
  const std::vector<SegmentError> errors = segment_errors(gt, est, options);
  m.segments = static_cast<int>(errors.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.translation_percent = m.rotation_deg_per_100m = errors.empty() ? nan : 0.0;
  for (const SegmentError& e : errors) {
    m.translation_percent += 100.0 * e.translation_ratio / errors.size();
    m.rotation_deg_per_100m += 100.0 * e.rotation_rad_per_m * 180.0 / M_PI / errors.size();
  }
  for (double length : options.segment_lengths_m) {
    double t = 0, r = 0;
    int k = 0;
    for (const SegmentError& e : errors) {
      if (e.length_m != length) continue;
      t += 100.0 * e.translation_ratio;
      r += 100.0 * e.rotation_rad_per_m * 180.0 / M_PI;
      ++k;
    }
    if (k == 0) continue;
    m.lengths_m.push_back(length);
    m.translation_percent_by_length.push_back(t / k);
    m.rotation_deg_per_100m_by_length.push_back(r / k);
  }
  m.ate_rmse_m = ate_rmse(gt, est);
  const Sim3Alignment sim3 = sim3_alignment(gt, est);
  m.sim3_scale = sim3.scale;
  m.ate_sim3_rmse_m = sim3.rmse_m;
  m.path_length_m = path_distances(gt).back();
  const Eigen::Isometry3d gt_end = gt.front().inverse() * gt.back();
  const Eigen::Isometry3d est_end = est.front().inverse() * est.back();
  m.end_point_error_percent = m.path_length_m > 0
                                  ? 100.0 * (gt_end.translation() - est_end.translation()).norm() /
                                        m.path_length_m
                                  : nan;
  return m;
}

}  // namespace loopscan::eval
