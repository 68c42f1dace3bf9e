#pragma once
// Odometry accuracy as the KITTI benchmark reports it: relative translation error (%) and rotation
// error (deg per 100 m) over segments of 100..800 m starting every 10th frame, plus the absolute
// trajectory error (RMSE after the best rigid alignment). Poses are camera-to-world.
#include <vector>

#include <Eigen/Geometry>

namespace loopscan::eval {

struct OdometryOptions {
  std::vector<double> segment_lengths_m = {100, 200, 300, 400, 500, 600, 700, 800};
  int step_frames = 10;
};

struct SegmentError {
  int first = 0, last = 0;
  double length_m = 0;
  double translation_ratio = 0;  // |t of inv(est delta) * gt delta| / length
  double rotation_rad_per_m = 0;
};

struct OdometryMetrics {
  int segments = 0;                      // 0: the trajectory is shorter than every length
  double translation_percent = 0;        // mean over segments (NaN without segments)
  double rotation_deg_per_100m = 0;
  std::vector<double> lengths_m;         // per length that had segments
  std::vector<double> translation_percent_by_length, rotation_deg_per_100m_by_length;
  double ate_rmse_m = 0;                 // after the rigid (no scale) least-squares alignment
  // The best similarity alignment (rotation, translation and one scale, evo's --correct_scale):
  // the scale that takes the estimate onto the ground truth (below 1: the estimate is too long)
  // and the RMSE after it. An ATE that falls far below ate_rmse_m is a scale error.
  double sim3_scale = 1;
  double ate_sim3_rmse_m = 0;
  double path_length_m = 0;              // ground truth
  double end_point_error_percent = 0;    // |est end - gt end| relative to the first pose / length
};

// Cumulative ground-truth path length at every frame.
std::vector<double> path_distances(const std::vector<Eigen::Isometry3d>& T_world_cam);

std::vector<SegmentError> segment_errors(const std::vector<Eigen::Isometry3d>& gt,
                                         const std::vector<Eigen::Isometry3d>& estimate,
                                         const OdometryOptions& options = {});

// RMSE of positions after aligning `estimate` to `gt` by the best rotation and translation.
double ate_rmse(const std::vector<Eigen::Isometry3d>& gt,
                const std::vector<Eigen::Isometry3d>& estimate);

struct Sim3Alignment {
  double scale = 1;   // applied to the estimate
  double rmse_m = 0;  // of positions after the alignment
};
// The best rotation, translation and scale taking the estimate's positions onto gt's (Umeyama);
// scale 1 and the rigid RMSE where the estimate does not move. Throws std::invalid_argument
// when the sizes differ.
Sim3Alignment sim3_alignment(const std::vector<Eigen::Vector3d>& gt,
                             const std::vector<Eigen::Vector3d>& estimate);
Sim3Alignment sim3_alignment(const std::vector<Eigen::Isometry3d>& gt,
                             const std::vector<Eigen::Isometry3d>& estimate);

// Throws std::invalid_argument when the sizes differ or fewer than 2 poses are given.
OdometryMetrics odometry_metrics(const std::vector<Eigen::Isometry3d>& gt,
                                 const std::vector<Eigen::Isometry3d>& estimate,
                                 const OdometryOptions& options = {});

}  // namespace loopscan::eval
