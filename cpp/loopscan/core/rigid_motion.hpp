#pragma once
// A rigid motion from a rotation vector (axis times angle, radians) and a translation: the
// parameterisation of the Gauss-Newton increments and the bundle adjustment's pose blocks; and
// the cross-product matrix their Jacobians are built of.
#include <Eigen/Geometry>

namespace loopscan {

inline Eigen::Isometry3d rigid_motion(const Eigen::Vector3d& rotation_vector,
                                      const Eigen::Vector3d& translation) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const double angle = rotation_vector.norm();
  if (angle > 0) T.linear() = Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
  T.translation() = translation;
  return T;
}

// [v]x: skew(v) * w == v.cross(w).
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace loopscan
