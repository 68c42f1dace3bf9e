#pragma once
// Readers for ground-truth trajectories (KITTI odometry poses, RobotCar positions).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace loopscan::io {

enum class GtFormat { Kitti, RobotCar };

// "kitti" or "robotcar" (case-insensitive); anything else throws std::invalid_argument.
GtFormat parse_gt_format(const std::string& name);

// The format of a ground-truth file from its first line: 12 numbers a line are KITTI poses, 3 are
// RobotCar positions (northing easting down); anything else is an InputError naming the line.
GtFormat detect_gt_format(const std::string& path);
// parse_gt_format, or detect_gt_format(path) for "auto".
GtFormat gt_format(const std::string& path, const std::string& name);

// KITTI odometry ground truth: 12 finite numbers a line, the 3x4 camera-to-world pose row-major;
// the 0-based line index is the frame id. Blank lines only at the end.
std::vector<Eigen::Matrix<double, 3, 4>> read_kitti_poses(const std::string& path);

// TUM trajectory (what evo reads): `timestamp tx ty tz qx qy qz qw` a line, `#` comments;
// timestamps increasing, quaternions of norm 1 +- 1e-3 (normalised). Errors name file and line.
struct TumPose {
  double time = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
};
std::vector<TumPose> read_tum_trajectory(const std::string& path);

// One position per frame id (0-based line index). Kitti: translation column of each pose;
// RobotCar: `northing easting down`, 3 finite numbers a line, returned in that order.
std::vector<Eigen::Vector3d> read_positions(const std::string& path, GtFormat format);

// One unit forward direction per frame id, in the positions' frame. Kitti: the camera's z axis;
// RobotCar (positions only): the direction of motion over +-2 m of track (zero where the
// vehicle stood still throughout).
std::vector<Eigen::Vector3d> read_headings(const std::string& path, GtFormat format);

}  // namespace loopscan::io
