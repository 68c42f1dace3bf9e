#include "outputs/simulation.hpp"

#include <filesystem>
#include <stdexcept>

#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/camera_settings.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/sodso.hpp"
#include "loopscan/io/vo_files.hpp"

namespace loopscan::cli {

LoadedTrajectory load_trajectory(const std::string& spec, const sim::WorldConfig& world) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon),
                    arg = colon == std::string::npos ? "" : spec.substr(colon + 1);
  LoadedTrajectory t;
  if (kind == "builtin") {
    t.trajectory = sim::make_builtin_trajectory(arg);
  } else if (kind == "kitti") {
    t.trajectory = sim::trajectory_from_kitti(io::read_kitti_poses(arg), arg);
  } else if (kind == "robotcar") {
    t.gps = true;
    t.gps_rows = io::read_positions(arg, io::GtFormat::RobotCar);
    t.trajectory = sim::trajectory_from_gps(t.gps_rows, arg);
  } else {
    throw std::invalid_argument("unknown trajectory '" + spec +
                                "' (expected builtin:city, builtin:short, kitti:FILE or "
                                "robotcar:FILE)");
  }
  // A world is built along the route: refuse one too large to build, naming the file.
  const std::string problem = sim::route_size_problem(t.trajectory.centres(), world);
  if (!problem.empty()) throw io::InputError(arg, 0, problem);
  return t;
}

Session simulate_session(const LoadedTrajectory& t, const sim::World& world,
                         const sim::Conditions& conditions, const sim::StereoCamera& camera,
                         const sim::VoSimConfig& vo, const std::vector<KeyframePose>& vo_poses) {
  Session s;
  if (vo_poses.empty()) {
    s.keyframe_ids = sim::select_keyframes(t.trajectory);
  } else {
    for (const KeyframePose& k : vo_poses) {
      if (k.id < 0 || static_cast<std::size_t>(k.id) >= t.trajectory.T_world_cam.size()) {
        throw std::invalid_argument("VO pose id " + std::to_string(k.id) +
                                    " has no ground-truth frame in the trajectory (" +
                                    std::to_string(t.trajectory.T_world_cam.size()) + " frames)");
      }
      s.keyframe_ids.push_back(k.id);
    }
  }
  s.vo = sim::simulate_vo(t.trajectory, s.keyframe_ids, world, conditions, camera, vo, vo_poses);
  s.parameters = {{"world", world.parameters()},
                  {"conditions",
                   {{"season", sim::season_name(conditions.season)},
                    {"illumination_gain", conditions.illumination_gain},
                    {"gamma", conditions.gamma},
                    {"session_seed", conditions.session_seed}}},
                  {"camera",
                   {{"fx", camera.fx},
                    {"fy", camera.fy},
                    {"cx", camera.cx},
                    {"cy", camera.cy},
                    {"width", camera.width},
                    {"height", camera.height},
                    {"bf", camera.bf}}},
                  {"vo",
                   {{"points_per_keyframe", vo.points_per_keyframe},
                    {"max_rays_per_keyframe", vo.max_rays_per_keyframe},
                    {"min_depth_m", vo.min_depth_m},
                    {"max_depth_m", vo.max_depth_m},
                    {"disparity_sigma_px", vo.disparity_sigma_px},
                    {"gradient_threshold", vo.gradient_threshold},
                    {"gray_noise", vo.gray_noise},
                    {"drift_translation_per_m", vo.drift_translation_per_m},
                    {"drift_rotation_deg_per_m", vo.drift_rotation_deg_per_m},
                    {"reset_keyframe_ids", vo.reset_keyframe_ids},
                    {"seed", vo.seed},
                    {"external_vo_poses", !vo_poses.empty()}}},
                  {"trajectory",
                   {{"name", t.trajectory.name},
                    {"frames", t.trajectory.T_world_cam.size()},
                    {"keyframes", s.keyframe_ids.size()}}},
                  {"result",
                   {{"points", s.vo.points.size()},
                    {"mean_points_per_keyframe", s.vo.mean_points_per_keyframe},
                    {"mean_rays_per_keyframe", s.vo.mean_rays_per_keyframe}}}};
  return s;
}

void write_session(const std::string& dir, const LoadedTrajectory& t, const Session& s) {
  std::filesystem::create_directories(dir);
  io::write_sodso_poses(dir + "/poses_history_file.txt", s.vo.poses);
  io::write_sodso_points(dir + "/pts_history_file.txt", s.vo.points);
  if (t.gps) {
    io::write_gps(dir + "/gt.txt", t.gps_rows);
  } else {
    std::vector<Eigen::Matrix<double, 3, 4>> gt;
    for (const Eigen::Isometry3d& T : t.trajectory.T_world_cam)
      gt.push_back(T.matrix().topRows<3>());
    io::write_kitti_poses(dir + "/gt.txt", gt);
  }
  io::write_file_atomic(dir + "/world.json", s.parameters.dump(1) + "\n");
}

void reload_session(const std::string& dir, const LoadedTrajectory& t, Session& s) {
  s.vo.poses = io::read_sodso_poses(dir + "/poses_history_file.txt");
  s.vo.points = io::read_sodso_points(dir + "/pts_history_file.txt");
  const io::GtFormat format = t.gps ? io::GtFormat::RobotCar : io::GtFormat::Kitti;
  s.gt_positions = io::read_positions(dir + "/gt.txt", format);
  s.gt_headings = io::read_headings(dir + "/gt.txt", format);
}

sim::StereoCamera load_camera(const std::string& yaml_path) {
  sim::StereoCamera c;
  if (yaml_path.empty()) return c;
  const io::StereoSettings s = io::read_orbslam_stereo(yaml_path);
  c.fx = s.fx;
  c.fy = s.fy;
  c.cx = s.cx;
  c.cy = s.cy;
  c.width = s.width;
  c.height = s.height;
  c.bf = s.bf;
  return c;
}

}  // namespace loopscan::cli
