// The pose helpers every stage shares: a camera's centre and a pose's yaw.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "loopscan/core/types.hpp"
#include "loopscan/core/yaw.hpp"

namespace loopscan {
namespace {

// camera_centre: the camera's world position, for any rotation (the world origin maps to t, so
// the centre maps to the camera's origin).
TEST(CameraCentre, IsWhereTheCameraIs) {
  const Eigen::Vector3d centre(3.0, -1.5, 42.0);
  for (const double angle : {0.0, 0.7, -2.9}) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(angle, Eigen::Vector3d(0.3, -1.0, 0.2).normalized()).toRotationMatrix();
    Pose3x4 T;
    T << R, -R * centre;
    EXPECT_LT((camera_centre(T) - centre).norm(), 1e-12) << angle;
  }
  Pose3x4 ahead = Pose3x4::Identity();  // a camera 7 m along +z, looking along +z
  ahead.col(3) = Eigen::Vector3d(0, 0, -7);
  EXPECT_LT((camera_centre(ahead) - Eigen::Vector3d(0, 0, 7)).norm(), 1e-15);
}

// yaw_of reads back the yaw yaw_rotation turned by, whatever else the pose holds (a
// translation, a small pitch), so a pose's yaw seeds ICP the right way round.
TEST(Yaw, YawOfIsTheInverseOfYawRotation) {
  for (const double yaw : {-3.0, -1.2, -0.1, 0.0, 0.4, 1.5, 3.1}) {
    Eigen::Isometry3d T = yaw_rotation(yaw) * Eigen::Translation3d(1.5, 0.2, -4.0);
    EXPECT_NEAR(yaw_of(T), yaw, 1e-12) << yaw;
    T.linear() = T.linear() * Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()).toRotationMatrix();
    EXPECT_NEAR(yaw_of(T), yaw, 1e-3) << yaw;
  }
}

}  // namespace
}  // namespace loopscan
