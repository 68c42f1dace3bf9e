#pragma once
// Plain value types shared by every loopscan module.
#include <Eigen/Core>
#include <vector>

namespace loopscan {

// Camera frame convention of the input (SO-DSO / KITTI): x right, y down, z forward.
struct PointI {
  Eigen::Vector3d p;
  float intensity = 0.f;  // gray value 0..255; float as in the reference implementation
};
using Cloud = std::vector<PointI>;

// One 3D point exported by the VO, in the VO world frame, tagged with its keyframe id.
struct IdPoint {
  int id = 0;
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
  float intensity = 0.f;
};

// A world-to-camera (or any rigid) transform as the top three rows of a 4x4 matrix.
using Pose3x4 = Eigen::Matrix<double, 3, 4>;

// One VO keyframe: id and world-to-camera transform (3x4, row-major in files).
struct KeyframePose {
  int id = 0;
  Eigen::Matrix<double, 3, 4> T_cam_world = Eigen::Matrix<double, 3, 4>::Identity();
};

// Where the camera of a world-to-camera transform is, in the world: -R^T t.
inline Eigen::Vector3d camera_centre(const Pose3x4& T_cam_world) {
  return -T_cam_world.leftCols<3>().transpose() * T_cam_world.col(3);
}

// `Reference` reproduces the authors' implementation including its defects;
// `Default` fixes them (see docs/reference-vs-default.md).
enum class Mode { Reference, Default };

// BirdsEye: the ground-plane place of core/descriptors/birds_eye_place.hpp (default mode only).
enum class Method { ScanContext, M2dp, Delight, BirdsEye };

}  // namespace loopscan
