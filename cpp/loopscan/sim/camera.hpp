#pragma once
// Rectified pinhole stereo camera (KITTI camera frame: x right, y down, z forward); files with
// its settings are read by io::read_orbslam_stereo.
#include <Eigen/Core>

namespace loopscan::sim {

struct StereoCamera {
  double fx = 718.856, fy = 718.856, cx = 607.1928, cy = 185.2157;
  int width = 1241, height = 376;
  double bf = 386.1448;  // focal * baseline, px * m

  // Pixel (u, v) of a camera-frame point; pixel centres at integer coordinates, the image covers
  // [-0.5, width - 0.5) x [-0.5, height - 0.5). False if z <= 0 (pixel untouched) or outside the
  // image (pixel still set).
  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& pixel) const;
  // Unit ray in the camera frame through pixel (u, v).
  Eigen::Vector3d ray(double u, double v) const;
  double baseline() const { return bf / fx; }  // metres
};

}  // namespace loopscan::sim
