#pragma once
// Robust point-to-plane ICP: aligns a source cloud onto a target cloud (points with normals),
// from an initial guess, with a shrinking correspondence distance and Geman-McClure weights.
// The result also says how well the alignment is constrained: the weakest direction of the
// translation (a corridor of facades leaves the along-street direction free).
#include <cstdint>

#include <Eigen/Geometry>
#include <vector>

#include "loopscan/closure/target_cloud.hpp"

namespace loopscan::closure {

struct IcpConfig {
  // Correspondence distances, one stage each, coarse to fine (metres).
  std::vector<double> stage_distances_m = {4.0, 2.0, 1.0, 0.6};
  // Source points used per stage (every n-th): coarse stages need few.
  std::vector<int> stage_strides = {4, 3, 2, 1};
  int max_iterations_per_stage = 12;
  // A step below both ends the stage. Between 0.5 m voxel clouds (closure.cloud.voxel_m) the
  // steps settle at about 1 cm and 0.3 mrad as correspondences switch from one voxel to the
  // next: a threshold below that is rarely met and only runs the stage to its last iteration.
  double converged_translation_m = 0.02;
  double converged_rotation_rad = 1e-3;
  double inlier_distance_m = 0.6;  // for overlap and rmse, after convergence
};

void validate(const IcpConfig& config);

struct IcpResult {
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
  int iterations = 0;
  int inliers = 0;       // source points within inlier_distance_m of the target
  double overlap = 0;    // inliers / source points, both among the structure points
  // RMS over the inliers of the distance to the target's local plane (to its nearest point
  // where the target has no normal): the fit, not the sampling of the two clouds.
  double rmse_m = 0;
  // Smallest eigenvalue of the translation block of the point-to-plane normal matrix, per
  // inlier: the mean squared component of the normals along the worst-constrained direction
  // (0: free, 1/3: isotropic).
  double translation_constraint = 0;
  double yaw_constraint = 0;  // the same for rotation about the up axis, per inlier, in m^2
  // sum(n n^T) per inlier with a normal (trace <= 1; I / 3 when every direction is alike).
  Eigen::Matrix3d translation_information = Eigen::Matrix3d::Zero();
  bool converged = false;
};

// The source's points [0, structure) count for the overlap (all of them by default).
IcpResult align_point_to_plane(const Points3f& source, const TargetCloud& target,
                               const Eigen::Isometry3d& initial, const IcpConfig& config = {},
                               std::size_t structure = SIZE_MAX);

// Overlap, rmse and constraint measures of `source` under a fixed transform.
IcpResult score_alignment(const Points3f& source, const TargetCloud& target,
                          const Eigen::Isometry3d& T_target_source, const IcpConfig& config = {},
                          std::size_t structure = SIZE_MAX);

}  // namespace loopscan::closure
