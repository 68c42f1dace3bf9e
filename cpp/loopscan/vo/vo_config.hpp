#pragma once
// Parameters of the stereo VO. Pixel sizes are given for KITTI's 1241-pixel-wide images and
// scaled with the image width (`pixel_scale`), so smaller renderings behave alike.
namespace loopscan::vo {

// Rectified stereo pinhole camera; the right camera sits `baseline_m` along the left's x axis.
struct StereoIntrinsics {
  double fx = 718.856, fy = 718.856, cx = 607.1928, cy = 185.2157, baseline_m = 0.5371657;
  int width = 1241, height = 376;
  double bf() const { return fx * baseline_m; }
  // A positive size, focal lengths in [1, 1e5] px, a principal point within +-1e5 px and a
  // baseline in (0, 100] m (what io::read_kitti_calib accepts).
  bool plausible() const {
    return width > 0 && height > 0 && fx >= 1 && fx <= 1e5 && fy >= 1 && fy <= 1e5 && cx >= -1e5 &&
           cx <= 1e5 && cy >= -1e5 && cy <= 1e5 && baseline_m > 0 && baseline_m <= 100;
  }
};

struct VoConfig {
  // Corners: one FAST corner (the strongest) per free grid cell.
  int grid_cols = 40, grid_rows = 12;
  int fast_threshold = 10;
  // Tracking: pyramidal Lucas-Kanade, forward-backward check.
  int klt_window_px = 21, klt_levels = 3;
  double forward_backward_px = 1.0;
  // Pose: P3P RANSAC, then Gauss-Newton on the inliers, each reprojection weighted by the
  // tracking noise plus its map point's stereo covariance seen from the frame (standard
  // deviations in px; the point's pixel noise is track_sigma_px, its disparity noise
  // stereo_sigma_px: 0 leaves no depth uncertainty).
  double ransac_reprojection_px = 2.0;
  int ransac_iterations = 100;
  double track_sigma_px = 1.0, stereo_sigma_px = 0.5;
  int min_inliers = 15;
  double max_step_m = 5.0;  // a larger jump between frames means tracking failed
  // Stereo matching (SAD over a square window along the row).
  int stereo_half_window = 2;
  double stereo_uniqueness = 0.85;  // best cost < uniqueness * second-best (away from the best)
  double min_depth_m = 1.0, max_depth_m = 80.0;
  // Keyframes: the simulator's policy (1.2 m or 5 degrees), or when tracks run low.
  double keyframe_distance_m = 1.2, keyframe_rotation_deg = 5.0;
  double keyframe_min_track_ratio = 0.5;
  // Windowed bundle adjustment (Ceres) over the most recent keyframes; the oldest are fixed.
  int window_keyframes = 7, fixed_keyframes = 2;
  int ba_iterations = 6;
  double ba_huber_px = 1.5;
  // The window's adjustment is applied after the next frame's tracking (Lucas-Kanade starts
  // from the pose and points before it), before that frame's pose. true: it runs on a worker
  // thread meanwhile; false: on the calling thread when it is applied. Same result either way.
  bool ba_on_worker = true;
  // Exported DSO-like points: the highest-gradient pixel of each block with a stereo depth, if
  // above max(point_min_gradient, median gradient of its 32x32 region + margin) as in DSO.
  int points_per_keyframe = 1000;
  double point_min_gradient = 8.0;          // gray levels per pixel (central differences / 2)
  double point_gradient_over_median = 7.0;  // DSO's setting_minGradHistAdd
  double point_max_depth_m = 45.0;
};

// Image-size factor for pixel parameters (1 at 1241 px width).
inline double pixel_scale(const StereoIntrinsics& c) { return c.width / 1241.0; }

}  // namespace loopscan::vo
