#pragma once
// What the VO picks in a keyframe's left image: corners to track (and which of them look alike
// along a line), and the DSO-like points it exports (high-gradient pixels with a stereo depth and
// their gray value).
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "loopscan/vo/stereo_match.hpp"
#include "loopscan/vo/vo_config.hpp"

namespace loopscan::vo {

// Disparity search range for depths in [min_depth_m, max_depth_m].
StereoSearch stereo_search_for(const StereoIntrinsics& camera, const VoConfig& config,
                               double min_depth_m, double max_depth_m, bool left_right_check);

// The strongest FAST corner of every grid cell that holds none of `occupied`.
std::vector<cv::Point2f> detect_grid_corners(const cv::Mat& image,
                                             const std::vector<cv::Point2f>& occupied,
                                             const VoConfig& config);

// Whether the image around p (11x11 px) looks like itself again 4-40 px further along
// `direction` (zero-mean normalised correlation above 0.8), is flat (RMS below 1 gray level) or
// too near the border to compare whole: a guard rail's beam or posts, a fence, the side of a
// lane line. A track there ends wherever along that line its search started. A zero direction:
// false.
bool self_similar_along(const cv::Mat& image, const cv::Point2f& p, const cv::Point2f& direction);

struct CameraPoint {
  Eigen::Vector3d p_cam;  // left camera frame
  float gray = 0;         // of the surface beside the edge (2 px along the gradient, flatter side)
  float u = 0, v = 0;  // pixel it was selected at
};

// Per block (sized for ~2 x points_per_keyframe blocks) the pixel of largest gradient, if above
// its region's threshold (VoConfig) and stereo-matched (left-right checked) within [min_depth_m,
// point_max_depth_m]; the points_per_keyframe strongest are kept.
std::vector<CameraPoint> select_gradient_points(const cv::Mat& left, const cv::Mat& right,
                                                const StereoIntrinsics& camera,
                                                const VoConfig& config);

// Camera-frame point of pixel (u, v) at disparity d.
inline Eigen::Vector3d back_project(const StereoIntrinsics& c, double u, double v, double d) {
  const double z = c.bf() / d;
  return {(u - c.cx) * z / c.fx, (v - c.cy) * z / c.fy, z};
}

}  // namespace loopscan::vo
