#pragma once
// Yaw: rotation about the camera's up axis (-y; x right, y down, z forward), positive to the
// left. A place's heading against a query's, and the turn that seeds an alignment.
#include <cmath>

#include <Eigen/Geometry>

namespace loopscan {

inline Eigen::Isometry3d yaw_rotation(double yaw_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d(0, -1, 0)).toRotationMatrix();
  return T;
}

// The yaw of a rotation, in yaw_rotation's sense (its inverse): where it turns the forward
// axis, read on the ground plane (a tilt is ignored).
inline double yaw_of(const Eigen::Matrix3d& R) { return std::atan2(-R(0, 2), R(2, 2)); }
inline double yaw_of(const Eigen::Isometry3d& T) { return yaw_of(Eigen::Matrix3d(T.linear())); }

}  // namespace loopscan
