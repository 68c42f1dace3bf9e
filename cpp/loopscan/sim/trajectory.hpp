#pragma once
// Camera trajectories for the simulator: built-in street routes, KITTI ground truth and
// RobotCar GPS tracks, plus a VO-like keyframe policy. Frames follow the KITTI camera
// convention (x right, y down, z forward); the world frame is camera-like (x, z horizontal,
// y down) and poses are camera-to-world.
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace loopscan::sim {

struct Trajectory {
  std::string name;
  std::vector<Eigen::Isometry3d> T_world_cam;  // one per frame; frame id = index
  std::vector<Eigen::Vector3d> centres() const;
};

// Built-in routes, driven at ~1 m per frame (right-hand traffic, lane 1.75 m off the street axis):
//  "city":  ~2 km through a street grid with several revisits, one street driven again in the
//           opposite direction, turns as circular arcs (smooth heading, no teleports).
//  "short": ~350 m, a block driven once and partly again, for tests.
//  "reverse": ~520 m, a street driven east, then its western half west (reverse revisits).
//  "highway": ~1.7 km of open road with long bends at 2.5 m per frame (25 m/s at 10 Hz), driven
//           once; meant for WorldConfig's open-road settings (docs/simulator.md).
// Any other name -> std::invalid_argument listing the names.
Trajectory make_builtin_trajectory(const std::string& name);
std::vector<std::string> builtin_trajectory_names();

// KITTI GT poses (3x4 camera-to-world, one per frame) -> trajectory as is.
Trajectory trajectory_from_kitti(const std::vector<Eigen::Matrix<double, 3, 4>>& poses,
                                 std::string name);

// RobotCar GPS rows (northing, easting, down) -> world (easting - e0, down - d0, northing - n0)
// with (n0, e0, d0) the first row. The heading is the motion direction over a window of
// `gps_heading_window_m`, ignoring position-fix jumps (steps far longer than their neighbours,
// as in RobotCar's INS tracks); stationary or duplicate frames keep the previous heading, the
// first frames take the first available one. Cameras look along the motion, level (no pitch/roll).
// Non-finite input -> std::invalid_argument naming the row.
inline constexpr double gps_heading_window_m = 4.0;
Trajectory trajectory_from_gps(const std::vector<Eigen::Vector3d>& northing_easting_down,
                               std::string name);

// The route driven `laps` times (1: the route itself). Unless the route ends where it starts
// (within 1.5 steps and 10 degrees), each lap after the first is reached by a connector: the
// shortest turn-straight-turn drive (Dubins) from the route's last pose to its first with turns
// of lap_connector_turn_radius_m, level cameras at the route's median step, the height linear.
// Frame ids run on across laps. Fewer than 2 frames, no motion or laps < 1 ->
// std::invalid_argument.
inline constexpr double lap_connector_turn_radius_m = 10.0;  // the built-in routes' right turns
Trajectory drive_laps(const Trajectory& route, int laps);
// drive_laps's connector alone (empty for a route that is a loop already).
std::vector<Eigen::Isometry3d> connector_back_to_start(const Trajectory& route);
// Where a world for drive_laps(route, laps) is built: the route's centres, and the connector's
// when laps > 1 (every lap drives the same streets).
std::vector<Eigen::Vector3d> lap_streets(const Trajectory& route, int laps);

struct KeyframeSelection {
  double min_distance_m = 1.2;
  double min_rotation_deg = 5.0;
};
// Frame ids of keyframes: the first frame, then every frame whose distance from the last keyframe
// or rotation angle relative to it exceeds a threshold (like a VO's keyframe policy).
std::vector<int> select_keyframes(const Trajectory& trajectory,
                                  const KeyframeSelection& selection = {});

// Level camera-to-world pose at `centre` looking along yaw (about the down axis; yaw 0 looks
// along +z, yaw pi/2 along +x).
Eigen::Isometry3d level_pose(const Eigen::Vector3d& centre, double yaw_rad);
// Yaw of the optical axis (z) of a camera-to-world pose, in (-pi, pi].
double heading_yaw(const Eigen::Isometry3d& T_world_cam);
// Rotation angle (rad) between the orientations of two poses.
double rotation_angle(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

}  // namespace loopscan::sim
