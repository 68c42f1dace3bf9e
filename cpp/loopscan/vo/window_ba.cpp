#include "loopscan/vo/window_ba.hpp"

#include <cmath>
#include <stdexcept>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "loopscan/core/rigid_motion.hpp"

namespace loopscan::vo {
namespace {

// Pose block: angle-axis (3) then translation (3), world-to-camera.
template <typename T>
void to_camera(const T* pose, const T* p_world, T* p_cam) {
  ceres::AngleAxisRotatePoint(pose, p_world, p_cam);
  for (int k = 0; k < 3; ++k) p_cam[k] += pose[3 + k];
}

struct StereoResidual {
  double u, v, u_right, fx, fy, cx, cy, bf;
  template <typename T>
  bool operator()(const T* pose, const T* point, T* r) const {
    T p[3];
    to_camera(pose, point, p);
    const T inv_z = T(1) / p[2];
    const T pu = fx * p[0] * inv_z + cx;
    r[0] = pu - u;
    r[1] = fy * p[1] * inv_z + cy - v;
    r[2] = pu - bf * inv_z - u_right;
    return true;
  }
};

struct MonoResidual {
  double u, v, fx, fy, cx, cy;
  template <typename T>
  bool operator()(const T* pose, const T* point, T* r) const {
    T p[3];
    to_camera(pose, point, p);
    const T inv_z = T(1) / p[2];
    r[0] = fx * p[0] * inv_z + cx - u;
    r[1] = fy * p[1] * inv_z + cy - v;
    return true;
  }
};

void pose_to_block(const Eigen::Isometry3d& T, double* block) {
  const Eigen::AngleAxisd aa(T.rotation());
  const Eigen::Vector3d r = aa.angle() * aa.axis();
  for (int k = 0; k < 3; ++k) {
    block[k] = r[k];
    block[3 + k] = T.translation()[k];
  }
}

Eigen::Isometry3d block_to_pose(const double* block) {
  return rigid_motion(Eigen::Vector3d(block[0], block[1], block[2]),
                      Eigen::Vector3d(block[3], block[4], block[5]));
}

}  // namespace

BaSummary bundle_adjust(BaProblem& problem, const StereoIntrinsics& c, int max_iterations,
                        double huber_px) {
  const std::size_t n_poses = problem.T_cam_world.size();
  if (problem.fixed.size() != n_poses) throw std::invalid_argument("bundle_adjust: fixed size");
  bool any_fixed = false;
  for (bool f : problem.fixed) any_fixed = any_fixed || f;
  if (!any_fixed) throw std::invalid_argument("bundle_adjust: no fixed pose (gauge)");
  std::vector<double> poses(6 * n_poses);
  for (std::size_t i = 0; i < n_poses; ++i) pose_to_block(problem.T_cam_world[i], &poses[6 * i]);
  std::vector<double> points(3 * problem.points.size());
  for (std::size_t i = 0; i < problem.points.size(); ++i)
    for (int k = 0; k < 3; ++k) points[3 * i + k] = problem.points[i][k];

  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(po);
  ceres::HuberLoss huber(huber_px);
  for (const BaObservation& o : problem.observations) {
    double* pose = &poses[6 * o.keyframe];
    double* point = &points[3 * o.point];
    if (std::isfinite(o.u_right)) {
      ceres_problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<StereoResidual, 3, 6, 3>(
              new StereoResidual{o.u, o.v, o.u_right, c.fx, c.fy, c.cx, c.cy, c.bf()}),
          &huber, pose, point);
    } else {
      ceres_problem.AddResidualBlock(new ceres::AutoDiffCostFunction<MonoResidual, 2, 6, 3>(
                                         new MonoResidual{o.u, o.v, c.fx, c.fy, c.cx, c.cy}),
                                     &huber, pose, point);
    }
  }
  for (std::size_t i = 0; i < n_poses; ++i) {
    if (problem.fixed[i] && ceres_problem.HasParameterBlock(&poses[6 * i]))
      ceres_problem.SetParameterBlockConstant(&poses[6 * i]);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &ceres_problem, &summary);

  for (std::size_t i = 0; i < n_poses; ++i)
    if (!problem.fixed[i]) problem.T_cam_world[i] = block_to_pose(&poses[6 * i]);
  for (std::size_t i = 0; i < problem.points.size(); ++i)
    problem.points[i] = Eigen::Vector3d(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
  return {summary.initial_cost, summary.final_cost,
          static_cast<int>(summary.iterations.size())};
}

double reprojection_error(const BaProblem& problem, const BaObservation& o,
                          const StereoIntrinsics& c) {
  const Eigen::Vector3d p = problem.T_cam_world[o.keyframe] * problem.points[o.point];
  if (p.z() <= 0) return std::numeric_limits<double>::infinity();
  const double u = c.fx * p.x() / p.z() + c.cx, v = c.fy * p.y() / p.z() + c.cy;
  double e = std::max(std::abs(u - o.u), std::abs(v - o.v));
  if (std::isfinite(o.u_right)) e = std::max(e, std::abs(u - c.bf() / p.z() - o.u_right));
  return e;
}

}  // namespace loopscan::vo
