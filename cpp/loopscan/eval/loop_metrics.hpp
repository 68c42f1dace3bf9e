#pragma once
// Trajectory and loop-closing metrics: evo's RPE over path-length deltas, and each loop's
// truth and relative-pose error against the ground truth. Poses are camera-to-world.
#include <vector>

#include <Eigen/Geometry>

namespace loopscan::eval {

struct RelativeError {
  int pairs = 0;
  double translation_rmse_m = 0;
  double rotation_rmse_deg = 0;
};

// evo's `evo_rpe --delta D --delta_unit m` (all_pairs off): the poses at which the estimated
// path since the previous such pose reaches `delta_m` (the first: since pose 0), consecutive
// ones paired; errors of (gt_i^-1 gt_j)^-1 (est_i^-1 est_j). Throws std::invalid_argument on mismatched
// sizes or a delta that is not positive.
RelativeError relative_pose_error(const std::vector<Eigen::Isometry3d>& gt,
                                  const std::vector<Eigen::Isometry3d>& estimate, double delta_m);

// The rigid transform (no scale) that best maps `estimate` onto `gt` (Umeyama), and the RMSE
// of the positions after it: evo's APE with --align. Throws on mismatched sizes.
Eigen::Isometry3d rigid_alignment(const std::vector<Eigen::Vector3d>& gt,
                                  const std::vector<Eigen::Vector3d>& estimate);
double aligned_rmse(const std::vector<Eigen::Vector3d>& gt,
                    const std::vector<Eigen::Vector3d>& estimate);

struct LoopTruth {
  double gt_distance_m = 0;  // between the two keyframes
  bool is_true = false;      // gt_distance_m <= the threshold
  double translation_error_m = 0;  // of the estimated relative pose against the ground truth's
  double rotation_error_deg = 0;
};

// T_query_match maps the match's camera frame into the query's.
LoopTruth loop_truth(const Eigen::Isometry3d& T_query_match, const Eigen::Isometry3d& gt_query,
                     const Eigen::Isometry3d& gt_match, double true_within_m = 10.0);

}  // namespace loopscan::eval
