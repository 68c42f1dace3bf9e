#include "loopscan/sim/camera.hpp"

#include <cmath>

namespace loopscan::sim {

bool StereoCamera::project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& pixel) const {
  if (!(p_cam.z() > 0.0)) return false;
  pixel = {fx * p_cam.x() / p_cam.z() + cx, fy * p_cam.y() / p_cam.z() + cy};
  return pixel.x() >= -0.5 && pixel.x() < width - 0.5 && pixel.y() >= -0.5 &&
         pixel.y() < height - 0.5;
}

Eigen::Vector3d StereoCamera::ray(double u, double v) const {
  return Eigen::Vector3d((u - cx) / fx, (v - cy) / fy, 1.0).normalized();
}

}  // namespace loopscan::sim
