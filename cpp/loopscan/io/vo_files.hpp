#pragma once
// Writers for what a VO exports (SO-DSO history files) and for ground truth, in the layouts
// the readers accept. All atomic.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "loopscan/core/types.hpp"

namespace loopscan::io {

// `id` + 12 numbers of the world-to-camera 3x4, row-major.
void write_sodso_poses(const std::string& path, const std::vector<KeyframePose>& poses);
// `id x y z intensity` (4 decimals for coordinates, 1 for intensity, as SO-DSO prints them).
void write_sodso_points(const std::string& path, const std::vector<IdPoint>& points);
// KITTI GT: 12 numbers a line (camera-to-world), line = frame id.
void write_kitti_poses(const std::string& path,
                       const std::vector<Eigen::Matrix<double, 3, 4>>& T_world_cam);
// TUM (what evo reads): `timestamp tx ty tz qx qy qz qw` a line, with a `#` header.
void write_tum_trajectory(const std::string& path, const std::vector<double>& times,
                          const std::vector<Eigen::Isometry3d>& T_world_body);
// RobotCar GPS layout: `northing easting down` a line.
void write_gps(const std::string& path, const std::vector<Eigen::Vector3d>& northing_easting_down);

}  // namespace loopscan::io
