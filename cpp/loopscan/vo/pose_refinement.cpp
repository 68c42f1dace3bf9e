#include "loopscan/vo/pose_refinement.hpp"

#include <cmath>
#include <cstddef>

#include <Eigen/Cholesky>

#include "loopscan/core/rigid_motion.hpp"

namespace loopscan::vo {

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

namespace {

struct Linearisation {
  double cost = 0;  // Huber on each Mahalanobis norm
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<Eigen::Matrix2d> information;  // per used point, at the linearisation pose
  bool finite = true;
};

// Over the points in `used`. Given `frozen` (the information matrices of an earlier
// linearisation), the cost alone under those weights: the cost that linearisation's step
// minimises, so that a step can be checked against it.
Linearisation linearise(const Eigen::Isometry3d& T, const std::vector<UncertainPoint>& points,
                        const std::vector<Eigen::Vector2d>& observations,
                        const std::vector<std::size_t>& used, const StereoIntrinsics& camera,
                        const PoseRefinementConfig& config,
                        const std::vector<Eigen::Matrix2d>* frozen = nullptr) {
  const bool with_derivatives = frozen == nullptr;
  const Eigen::Matrix2d pixel_noise =
      Eigen::Matrix2d::Identity() * config.sigma_px * config.sigma_px;
  const double k = config.huber_mahalanobis;
  Linearisation out;
  for (std::size_t u = 0; u < used.size(); ++u) {
    const std::size_t i = used[u];
    const Eigen::Vector3d p = T * points[i].position;
    // A point that the step took behind the camera counts as far off as the loss allows.
    if (!(p.z() > config.min_depth_m)) {
      out.cost += k * k;
      if (with_derivatives) out.information.push_back(Eigen::Matrix2d::Zero());
      continue;
    }
    const double iz = 1.0 / p.z();
    const Eigen::Vector2d r(camera.fx * p.x() * iz + camera.cx - observations[i].x(),
                            camera.fy * p.y() * iz + camera.cy - observations[i].y());
    // Huber on the Mahalanobis norm: a track that lost its point counts only linearly.
    const auto huber = [&](const Eigen::Matrix2d& information) {
      const double m = std::sqrt(r.dot(information * r));
      out.cost += m <= k ? 0.5 * m * m : k * (m - 0.5 * k);
      return m <= k ? 1.0 : k / m;  // the robust weight
    };
    if (!with_derivatives) {
      huber((*frozen)[u]);
      continue;
    }
    Eigen::Matrix<double, 2, 3> J_proj;
    J_proj << camera.fx * iz, 0, -camera.fx * p.x() * iz * iz, 0, camera.fy * iz,
        -camera.fy * p.y() * iz * iz;
    const Eigen::Matrix<double, 2, 3> J_point = J_proj * T.linear();
    Eigen::Matrix2d information =
        (pixel_noise + J_point * points[i].covariance * J_point.transpose()).inverse();
    if (!information.allFinite()) information.setZero();
    out.information.push_back(information);
    const double robust = huber(information);
    Eigen::Matrix<double, 3, 6> J_twist;  // d p / d (rotation, translation), left increment
    J_twist << -skew(p), Eigen::Matrix3d::Identity();
    const Eigen::Matrix<double, 2, 6> J = J_proj * J_twist;
    out.H += robust * J.transpose() * information * J;
    out.g += robust * J.transpose() * information * r;
  }
  out.finite = std::isfinite(out.cost) && out.H.allFinite() && out.g.allFinite();
  return out;
}

}  // namespace

bool refine_pose(Eigen::Isometry3d& T_cam_world, const std::vector<UncertainPoint>& points,
                 const std::vector<Eigen::Vector2d>& observations, const StereoIntrinsics& camera,
                 const PoseRefinementConfig& config) {
  if (points.size() != observations.size()) return false;
  // The points in front of the starting pose, with finite data; the set stays fixed so that
  // every iteration minimises the same cost.
  std::vector<std::size_t> used;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i].position.allFinite() && points[i].covariance.allFinite() &&
        observations[i].allFinite() && (T_cam_world * points[i].position).z() > config.min_depth_m)
      used.push_back(i);
  if (used.size() < 3) return false;
  Eigen::Isometry3d T = T_cam_world;
  for (int iteration = 0; iteration < config.iterations; ++iteration) {
    const Linearisation now = linearise(T, points, observations, used, camera, config);
    if (!now.finite) return false;
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> solver(now.H);
    if (solver.info() != Eigen::Success) return false;
    Eigen::Matrix<double, 6, 1> step = solver.solve(-now.g);
    if (!step.allFinite()) return false;
    // Gauss-Newton's step, halved until the cost falls (at most 5 times): none that falls ends.
    bool improved = false;
    for (int halving = 0; halving <= 5; ++halving) {
      const Eigen::Isometry3d candidate = rigid_motion(step.head<3>(), step.tail<3>()) * T;
      const Linearisation next =
          linearise(candidate, points, observations, used, camera, config, &now.information);
      if (next.finite && next.cost <= now.cost) {
        T = candidate;
        improved = true;
        break;
      }
      step *= 0.5;
    }
    if (!improved || step.norm() < 1e-10) break;
  }
  T_cam_world = T;
  return true;
}

}  // namespace loopscan::vo
