#include "loopscan/closure/icp.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "loopscan/core/rigid_motion.hpp"

namespace loopscan::closure {
namespace {

constexpr int kMinCorrespondences = 12;
constexpr double kPointToPointWeight = 0.3;

// The camera's up axis (-y in the KITTI / DSO camera frame): the yaw axis.
const Eigen::Vector3d kUp(0.0, -1.0, 0.0);

Eigen::Isometry3d exp_se3(const Eigen::Matrix<double, 6, 1>& delta) {
  return rigid_motion(delta.tail<3>(), delta.head<3>());
}

// One Gauss-Newton step over every `stride`-th source point's correspondence within
// `max_distance`; false when too few. `hints` holds each source point's last correspondence.
bool step(const Points3f& source, std::size_t stride, const TargetCloud& target,
          const Eigen::Isometry3d& T, double max_distance, std::vector<int>& hints,
          Eigen::Matrix<double, 6, 1>& delta) {
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  const double sigma2 = (max_distance / 3.0) * (max_distance / 3.0);
  const float max_d2 = static_cast<float>(max_distance * max_distance);
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  int used = 0;
  const auto add = [&](const Eigen::Matrix<double, 6, 1>& J, double r, double weight) {
    const double u = 1.0 + r * r / sigma2;
    const double w = weight / (u * u);  // Geman-McClure
    H.noalias() += w * J * J.transpose();
    g.noalias() += w * r * J;
  };
  for (std::size_t i = 0; i < source.size(); i += stride) {
    const Eigen::Vector3f p = R * source[i] + t;
    const int j = target.nearest(p, max_d2, nullptr, hints[i]);
    if (j < 0) continue;
    hints[i] = j;
    const Eigen::Vector3d pd = p.cast<double>();
    const Eigen::Vector3d d = pd - target.points()[std::size_t(j)].cast<double>();
    if (target.has_normal(j)) {
      const Eigen::Vector3d n = target.normal(j).cast<double>();
      Eigen::Matrix<double, 6, 1> J;
      J << n, pd.cross(n);
      add(J, n.dot(d), 1.0);
    } else {
      // Sparse stereo points often have no plane around them: point-to-point, down-weighted
      // (the nearest point is only near the surface, not on the source point's spot).
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
        Eigen::Matrix<double, 6, 1> J;
        J << e, pd.cross(e);
        add(J, d[k], kPointToPointWeight);
      }
    }
    ++used;
  }
  if (used < kMinCorrespondences) return false;
  H.diagonal().array() += 1e-6 * (H.trace() / 6.0 + 1e-9);
  delta = H.ldlt().solve(-g);
  return delta.allFinite();
}

}  // namespace

void validate(const IcpConfig& c) {
  const auto fail = [](const char* what) { throw std::invalid_argument(std::string("icp config: ") + what); };
  if (c.stage_distances_m.empty() || c.stage_distances_m.size() > 16 ||
      c.stage_strides.size() != c.stage_distances_m.size()) {
    fail("1 to 16 stages, one stride per stage distance");
  }
  for (std::size_t i = 0; i < c.stage_distances_m.size(); ++i) {
    if (!(c.stage_distances_m[i] > 0 && c.stage_distances_m[i] <= 100)) fail("stage distances in (0, 100]");
    if (c.stage_strides[i] < 1 || c.stage_strides[i] > 1000) fail("strides in [1, 1000]");
  }
  if (c.max_iterations_per_stage < 1 || c.max_iterations_per_stage > 1000) fail("max_iterations_per_stage in [1, 1000]");
  if (!(c.converged_translation_m > 0) || !(c.converged_rotation_rad > 0)) fail("convergence thresholds > 0");
  if (!(c.inlier_distance_m > 0 && c.inlier_distance_m <= 100)) fail("inlier_distance_m in (0, 100]");
}

namespace {

IcpResult score(const Points3f& source, const TargetCloud& target, const Eigen::Isometry3d& T,
                const IcpConfig& config, std::size_t structure, const std::vector<int>* hints) {
  structure = std::min(structure, source.size());
  int structure_inliers = 0;
  IcpResult r;
  r.T_target_source = T;
  const float max_d2 = static_cast<float>(config.inlier_distance_m * config.inlier_distance_m);
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  Eigen::Matrix3d Htt = Eigen::Matrix3d::Zero();
  double yaw = 0, sum_d2 = 0;
  int with_normal = 0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const Eigen::Vector3f p = R * source[i] + t;
    float d2 = 0;
    const int j = target.nearest(p, max_d2, &d2, hints ? (*hints)[i] : -1);
    if (j < 0) continue;
    ++r.inliers;
    structure_inliers += i < structure;
    if (!target.has_normal(j)) {
      sum_d2 += d2;
      continue;
    }
    const Eigen::Vector3d n = target.normal(j).cast<double>();
    const double along = n.dot((p - target.points()[std::size_t(j)]).cast<double>());
    sum_d2 += along * along;
    Htt += n * n.transpose();
    const double a = kUp.dot(p.cast<double>().cross(n));
    yaw += a * a;
    ++with_normal;
  }
  r.overlap = structure == 0 ? 0.0 : double(structure_inliers) / double(structure);
  r.rmse_m = r.inliers > 0 ? std::sqrt(sum_d2 / r.inliers) : 0.0;
  if (with_normal > 0) {
    r.translation_information = Htt / with_normal;
    r.translation_constraint =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(Htt, Eigen::EigenvaluesOnly)
            .eigenvalues()[0] / with_normal;
    r.yaw_constraint = yaw / with_normal;
  }
  return r;
}

}  // namespace

IcpResult score_alignment(const Points3f& source, const TargetCloud& target,
                          const Eigen::Isometry3d& T, const IcpConfig& config,
                          std::size_t structure) {
  return score(source, target, T, config, structure, nullptr);
}

IcpResult align_point_to_plane(const Points3f& source, const TargetCloud& target,
                               const Eigen::Isometry3d& initial, const IcpConfig& config,
                               std::size_t structure) {
  validate(config);
  Eigen::Isometry3d T = initial;
  int iterations = 0;
  bool converged = false;
  std::vector<int> hints(source.size(), -1);
  for (std::size_t stage = 0; stage < config.stage_distances_m.size(); ++stage) {
    const std::size_t stride = std::size_t(config.stage_strides[stage]);
    converged = false;
    for (int it = 0; it < config.max_iterations_per_stage; ++it) {
      Eigen::Matrix<double, 6, 1> delta;
      ++iterations;
      if (!step(source, stride, target, T, config.stage_distances_m[stage], hints, delta)) break;
      T = exp_se3(delta) * T;
      if (delta.head<3>().norm() < config.converged_translation_m &&
          delta.tail<3>().norm() < config.converged_rotation_rad) {
        converged = true;
        break;
      }
    }
  }
  IcpResult r = score(source, target, T, config, structure, &hints);
  r.iterations = iterations;
  r.converged = converged;
  return r;
}

}  // namespace loopscan::closure
