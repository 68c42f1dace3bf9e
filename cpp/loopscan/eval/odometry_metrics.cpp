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

// The poses' positions as columns.
Eigen::Matrix3Xd positions(const std::vector<Eigen::Isometry3d>& T) {
  Eigen::Matrix3Xd p(3, T.size());
  for (std::size_t i = 0; i < T.size(); ++i)
    p.col(static_cast<Eigen::Index>(i)) = T[i].translation();
  return p;
}

// The best rotation and translation, and with `with_scale` one scale (unless the estimate does
// not move: nothing to scale), taking the estimate's columns onto the ground truth's (Umeyama),
// and the RMSE after it.
Sim3Alignment fitted(const Eigen::Matrix3Xd& estimate, const Eigen::Matrix3Xd& gt,
                     bool with_scale) {
  Sim3Alignment out;
  if (gt.cols() == 0) return out;
  const bool scaled =
      with_scale && (estimate.colwise() - estimate.rowwise().mean()).squaredNorm() > 0;
  const Eigen::Matrix4d A = Eigen::umeyama(estimate, gt, scaled);
  const Eigen::Matrix3d sR = A.topLeftCorner<3, 3>();
  if (scaled) out.scale = std::cbrt(sR.determinant());
  const Eigen::Matrix3Xd aligned = (sR * estimate).colwise() + A.topRightCorner<3, 1>();
  out.rmse_m = std::sqrt((aligned - gt).colwise().squaredNorm().mean());
  return out;
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
  return fitted(positions(est), positions(gt), false).rmse_m;
}

Sim3Alignment sim3_alignment(const std::vector<Eigen::Vector3d>& gt,
                             const std::vector<Eigen::Vector3d>& est) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("sim3 alignment: " + std::to_string(est.size()) +
                                " estimated positions for " + std::to_string(gt.size()) +
                                " ground-truth ones");
  }
  const auto columns = [](const std::vector<Eigen::Vector3d>& p) {
    Eigen::Matrix3Xd m(3, p.size());
    for (std::size_t i = 0; i < p.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = p[i];
    return m;
  };
  return fitted(columns(est), columns(gt), true);
}

Sim3Alignment sim3_alignment(const std::vector<Eigen::Isometry3d>& gt,
                             const std::vector<Eigen::Isometry3d>& est) {
  check_sizes(gt, est);
  return fitted(positions(est), positions(gt), true);
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
  const Eigen::Matrix3Xd est_positions = positions(est), gt_positions = positions(gt);
  m.ate_rmse_m = fitted(est_positions, gt_positions, false).rmse_m;
  const Sim3Alignment sim3 = fitted(est_positions, gt_positions, true);
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
