#include "loopscan/vo/pose_refinement.hpp"

#include <cmath>

#include <Eigen/Cholesky>

#include "loopscan/core/rigid_motion.hpp"

namespace loopscan::vo {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace

Eigen::Matrix3d stereo_point_covariance(const StereoIntrinsics& c, double u, double v,
                                        double disparity, double sigma_px,
                                        double sigma_disparity_px) {
  const double z = c.bf() / disparity;
  const double dz_dd = -z / disparity;
  Eigen::Matrix3d J;  // d(x, y, z) / d(u, v, d)
  J << z / c.fx, 0, (u - c.cx) / c.fx * dz_dd, 0, z / c.fy, (v - c.cy) / c.fy * dz_dd, 0, 0, dz_dd;
  const Eigen::Vector3d variance(sigma_px * sigma_px, sigma_px * sigma_px,
                                 sigma_disparity_px * sigma_disparity_px);
  return J * variance.asDiagonal() * J.transpose();
}

bool refine_pose(Eigen::Isometry3d& T_cam_world, const std::vector<UncertainPoint>& points,
                 const std::vector<Eigen::Vector2d>& observations, const StereoIntrinsics& camera,
                 const PoseRefinementConfig& config) {
  const Eigen::Matrix2d pixel_noise =
      Eigen::Matrix2d::Identity() * config.sigma_px * config.sigma_px;
  Eigen::Isometry3d T = T_cam_world;
  for (int iteration = 0; iteration < config.iterations; ++iteration) {
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    int used = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d p = T * points[i].position;
      if (!(p.z() > 1e-6)) continue;
      const double iz = 1.0 / p.z();
      Eigen::Matrix<double, 2, 3> J_proj;
      J_proj << camera.fx * iz, 0, -camera.fx * p.x() * iz * iz, 0, camera.fy * iz,
          -camera.fy * p.y() * iz * iz;
      const Eigen::Vector2d r(camera.fx * p.x() * iz + camera.cx - observations[i].x(),
                              camera.fy * p.y() * iz + camera.cy - observations[i].y());
      const Eigen::Matrix<double, 2, 3> J_point = J_proj * T.linear();
      const Eigen::Matrix2d cov =
          pixel_noise + J_point * points[i].covariance * J_point.transpose();
      const Eigen::Matrix2d information = cov.inverse();
      if (!information.allFinite()) continue;
      // Huber on the Mahalanobis norm: a track that lost its point counts only linearly.
      const double mahalanobis = std::sqrt(r.dot(information * r));
      const double robust =
          mahalanobis <= config.huber_mahalanobis ? 1.0 : config.huber_mahalanobis / mahalanobis;
      Eigen::Matrix<double, 3, 6> J_twist;  // d p / d (rotation, translation), left increment
      J_twist << -skew(p), Eigen::Matrix3d::Identity();
      const Eigen::Matrix<double, 2, 6> J = J_proj * J_twist;
      H += robust * J.transpose() * information * J;
      g += robust * J.transpose() * information * r;
      ++used;
    }
    if (used < 3) return false;
    const Eigen::Matrix<double, 6, 1> step = H.ldlt().solve(-g);
    if (!step.allFinite()) return false;
    T = rigid_motion(step.head<3>(), step.tail<3>()) * T;  // applied on the left
    if (step.norm() < 1e-10) break;
  }
  T_cam_world = T;
  return true;
}

}  // namespace loopscan::vo
