#pragma once
// Windowed bundle adjustment (Ceres): keyframe poses and the points they observe, stereo
// reprojection residuals (left u, v and, where matched, right u) under a Huber loss.
#include <vector>

#include <Eigen/Geometry>

#include "loopscan/vo/vo_config.hpp"

namespace loopscan::vo {

struct BaObservation {
  int keyframe = 0;  // index into BaProblem::T_cam_world
  int point = 0;     // index into BaProblem::points
  double u = 0, v = 0;
  double u_right = 0;  // NaN when the observation has no right-image match
};

struct BaProblem {
  std::vector<Eigen::Isometry3d> T_cam_world;  // world-to-camera, one per keyframe
  std::vector<bool> fixed;                     // poses held constant (the gauge)
  std::vector<Eigen::Vector3d> points;
  std::vector<BaObservation> observations;
};

struct BaSummary {
  double initial_cost = 0, final_cost = 0;
  int iterations = 0;
};

// Optimises the non-fixed poses and all points in place. Needs at least one fixed pose.
BaSummary bundle_adjust(BaProblem& problem, const StereoIntrinsics& camera, int max_iterations,
                        double huber_px);

// Left/right reprojection error (px) of one observation (max over the residuals).
double reprojection_error(const BaProblem& problem, const BaObservation& o,
                          const StereoIntrinsics& camera);

}  // namespace loopscan::vo
