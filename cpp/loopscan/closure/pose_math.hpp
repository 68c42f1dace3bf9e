#pragma once
// Pose helpers the closure module's sources share (namespace detail, not an API): 3x4
// matrices to isometries, the nearest rotation.
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "loopscan/core/types.hpp"

namespace loopscan::closure::detail {

inline Eigen::Isometry3d isometry(const Pose3x4& T) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = T.leftCols<3>();
  out.translation() = T.col(3);
  return out;
}

// The nearest rotation (SVD): poses written with a few digits, or chained from such, are not
// quite orthonormal, and a rigid inverse of them misplaces points far from the origin (1e-4
// of non-orthonormality at 1 km: 0.1 m a pose, compounding along the odometry).
inline KeyframePose orthonormalised(KeyframePose k) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(Eigen::Matrix3d(k.T_cam_world.leftCols<3>()),
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0) {
    Eigen::Matrix3d U = svd.matrixU();
    U.col(2) *= -1;
    R = U * svd.matrixV().transpose();
  }
  k.T_cam_world.leftCols<3>() = R;
  return k;
}

inline double rotation_angle(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle(); }

}  // namespace loopscan::closure::detail
