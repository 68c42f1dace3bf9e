#pragma once
// Camera pose from 2D tracks of 3D points whose positions are uncertain: each reprojection is
// weighted by its own covariance in the image, the tracking noise plus the point's covariance
// carried through the projection. A far point triangulated from a small disparity is uncertain
// along its ray; from another viewpoint that ray's uncertainty shows up as image displacement,
// and the point is trusted less there.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "loopscan/vo/vo_config.hpp"

namespace loopscan::vo {

struct UncertainPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// Covariance of a stereo-triangulated point (left pixel u, v and disparity d, each with its own
// standard deviation in pixels), in the camera frame of the stereo pair.
Eigen::Matrix3d stereo_point_covariance(const StereoIntrinsics& camera, double u, double v,
                                        double disparity, double sigma_px,
                                        double sigma_disparity_px);

struct PoseRefinementConfig {
  double sigma_px = 0.5;           // tracking noise per image axis
  double huber_mahalanobis = 2.5;  // robust loss threshold on the whitened residual's norm
  int iterations = 10;
  double min_depth_m = 0.1;  // nearer points (in the camera frame) are left out
};

// Refines world-to-camera T_cam_world by Gauss-Newton on the covariance-whitened residuals
// (Huber-weighted), starting from the given pose; a step that does not lower the cost is halved
// (at most 5 times), then the refinement ends. Points nearer than min_depth_m at the start and
// non-finite data are left out. Returns false (T unchanged) when sizes differ, fewer than three
// points are usable or the system is not finite.
bool refine_pose(Eigen::Isometry3d& T_cam_world, const std::vector<UncertainPoint>& points,
                 const std::vector<Eigen::Vector2d>& observations, const StereoIntrinsics& camera,
                 const PoseRefinementConfig& config = {});

}  // namespace loopscan::vo
