#pragma once
// Shared by `simulate` and `demo`: trajectories from a spec string, sessions of the simulator.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "loopscan/sim/vo_simulator.hpp"

namespace loopscan::cli {

struct LoadedTrajectory {
  sim::Trajectory trajectory;
  bool gps = false;                       // RobotCar input: ground truth written as GPS rows
  std::vector<Eigen::Vector3d> gps_rows;  // northing easting down
};

// "builtin:city" | "builtin:short" | "builtin:reverse" | "kitti:FILE" | "robotcar:FILE"; a route
// beyond `world`'s bounds (max_route_length_m, max_extent_m) is refused naming the file.
LoadedTrajectory load_trajectory(const std::string& spec, const sim::WorldConfig& world);

// The KITTI 04-12 camera, or the one an ORB-SLAM2 settings yaml describes (--calib).
sim::StereoCamera load_camera(const std::string& yaml_path);

struct Session {
  sim::VoOutput vo;
  std::vector<int> keyframe_ids;
  nlohmann::json parameters;  // every parameter used
  // Ground truth per frame id as `evaluate` reads it from gt.txt (set by reload_session).
  std::vector<Eigen::Vector3d> gt_positions, gt_headings;
};

// One drive through `world` under `conditions`.
Session simulate_session(const LoadedTrajectory& t, const sim::World& world,
                         const sim::Conditions& conditions, const sim::StereoCamera& camera,
                         const sim::VoSimConfig& vo, const std::vector<KeyframePose>& vo_poses);

// Writes poses_history_file.txt, pts_history_file.txt, gt.txt, world.json into `dir`.
void write_session(const std::string& dir, const LoadedTrajectory& t, const Session& s);

// Replaces the session's poses and points by what `describe` reads back from `dir` (the
// SO-DSO files round them) and sets its ground truth from gt.txt: numbers computed from the
// reloaded session are what `describe` + `evaluate` on the files give.
void reload_session(const std::string& dir, const LoadedTrajectory& t, Session& s);

}  // namespace loopscan::cli
