#include "outputs/vo.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/progress.hpp"
#include "loopscan/eval/loop_metrics.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/vo_files.hpp"
#include "loopscan/vo/euroc.hpp"

namespace loopscan::cli {
namespace {

// `vo --euroc` against a TUM ground truth: evo's APE with --align and RPE with --delta D
// --delta_unit m. Frames are matched to ground-truth rows by timestamp (nearest, within 5 ms);
// throws io::InputError naming the file when fewer than 2 frames match.
nlohmann::json tum_metrics(const std::vector<double>& times,
                           const std::vector<Eigen::Isometry3d>& T_world_body,
                           const std::vector<io::TumPose>& gt, const std::string& gt_path,
                           double rpe_delta_m) {
  std::vector<Eigen::Isometry3d> gt_poses, estimate;
  std::vector<Eigen::Vector3d> gt_positions, positions;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const auto after = std::lower_bound(gt.begin(), gt.end(), times[i],
                                        [](const io::TumPose& p, double t) { return p.time < t; });
    const io::TumPose* best = nullptr;
    for (auto it : {after, after == gt.begin() ? gt.end() : after - 1}) {
      if (it != gt.end() &&
          (!best || std::abs(it->time - times[i]) < std::abs(best->time - times[i])))
        best = &*it;
    }
    if (!best || std::abs(best->time - times[i]) > 0.005) continue;
    gt_poses.push_back(best->T_world_body);
    estimate.push_back(T_world_body[i]);
    gt_positions.push_back(best->T_world_body.translation());
    positions.push_back(T_world_body[i].translation());
  }
  if (gt_poses.size() < 2)
    throw io::InputError(gt_path, 0,
                         "ground-truth rows within 5 ms of at least 2 frames (matched " +
                             std::to_string(gt_poses.size()) + " of " +
                             std::to_string(times.size()) + ")");
  double path = 0;
  for (std::size_t i = 1; i < gt_positions.size(); ++i)
    path += (gt_positions[i] - gt_positions[i - 1]).norm();
  const double ate = eval::aligned_rmse(gt_positions, positions);
  const eval::Sim3Alignment sim3 = eval::sim3_alignment(gt_positions, positions);
  const eval::RelativeError rpe = eval::relative_pose_error(gt_poses, estimate, rpe_delta_m);
  return {{"ground_truth", gt_path},
          {"matched_frames", gt_poses.size()},
          {"path_length_m", path},
          {"ate_rmse_m", ate},
          {"ate_percent_of_path", path > 0 ? 100.0 * ate / path : 0.0},
          {"sim3_scale", sim3.scale},
          {"ate_sim3_rmse_m", sim3.rmse_m},
          {"rpe_delta_m", rpe_delta_m},
          {"rpe_pairs", rpe.pairs},
          {"rpe_translation_rmse_m", rpe.translation_rmse_m},
          {"rpe_rotation_rmse_deg", rpe.rotation_rmse_deg}};
}

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nullptr; }

nlohmann::json metrics_json(const eval::OdometryMetrics& m) {
  nlohmann::json by_length = nlohmann::json::array();
  for (std::size_t i = 0; i < m.lengths_m.size(); ++i) {
    by_length.push_back({{"length_m", m.lengths_m[i]},
                         {"translation_percent", m.translation_percent_by_length[i]},
                         {"rotation_deg_per_100m", m.rotation_deg_per_100m_by_length[i]}});
  }
  return {{"segments", m.segments},
          {"translation_percent", number_or_null(m.translation_percent)},
          {"rotation_deg_per_100m", number_or_null(m.rotation_deg_per_100m)},
          {"by_length", by_length},
          {"ate_rmse_m", m.ate_rmse_m},
          {"sim3_scale", m.sim3_scale},
          {"ate_sim3_rmse_m", m.ate_sim3_rmse_m},
          {"path_length_m", m.path_length_m},
          {"end_point_error_percent", number_or_null(m.end_point_error_percent)}};
}

}  // namespace

void add_vo_options(CLI::App& cmd, VoArgs& a, bool allow_euroc) {
  CLI::Option* kitti = cmd.add_option(
      "--kitti", a.kitti, "KITTI odometry sequence dir (image_0/, image_1/, calib.txt)");
  if (allow_euroc) {
    CLI::Option* euroc =
        cmd.add_option("--euroc", a.euroc,
                       "raw stereo camera, EuRoC layout (mav0/cam0, cam1: data/, data.csv, "
                       "sensor.yaml); rectified before the VO; --gt: a TUM trajectory");
    kitti->excludes(euroc);
  } else {
    kitti->required();
  }
  cmd.add_option("--out", a.out, "output directory")->required();
  cmd.add_option("--gt", a.gt, "KITTI ground-truth poses (default: <kitti>/poses.txt if present)");
  cmd.add_option("--first", a.first, "first frame")
      ->check(finite_in(0, kMaxCount))
      ->capture_default_str();
  cmd.add_option("--frames", a.frames, "number of frames (default: all)")
      ->check(finite_in(0, kMaxCount));
  cmd.add_option("--blank-frames", a.blank_frames, "frames replaced by black images (tests resets)")
      ->check(finite_in(0, kMaxCount));
  cmd.add_flag("--quiet", a.quiet, "no progress bars or per-part summary lines");
}

VoResult run_vo_and_write(const VoArgs& a, const Configuration& c) {
  if (a.kitti.empty() == a.euroc.empty())
    throw std::invalid_argument("give --kitti DIR or --euroc DIR");
  const bool euroc = !a.euroc.empty();
  vo::EurocSequence raw;
  if (euroc) raw = vo::open_euroc_sequence(a.euroc);
  // A TUM ground truth is checked before the VO runs.
  const std::vector<io::TumPose> tum_gt =
      euroc && !a.gt.empty() ? io::read_tum_trajectory(a.gt) : std::vector<io::TumPose>{};
  const io::KittiSequence sequence = euroc ? raw.files : io::open_kitti_sequence(a.kitti);
  VoResult result;
  result.gt_path = euroc ? "" : a.gt;
  if (!euroc && result.gt_path.empty() && std::filesystem::exists(a.kitti + "/poses.txt"))
    result.gt_path = a.kitti + "/poses.txt";
  std::vector<Eigen::Matrix<double, 3, 4>>& gt_rows = result.gt_poses;
  if (!result.gt_path.empty()) {
    gt_rows = io::read_kitti_poses(result.gt_path);
    if (gt_rows.size() < sequence.frames()) {
      throw io::InputError(result.gt_path, gt_rows.size() + 1,
                           "one pose per frame (" + std::to_string(sequence.frames()) +
                               " frames in " + a.kitti + ")");
    }
  }
  const vo::VoConfig& config = c.vo;
  vo::SequenceRunOptions options;
  options.first = a.first;
  options.frames = a.frames;
  options.blank_frames = a.blank_frames;
  StepProgress progress("stereo VO", "frames", a.quiet);
  options.progress = [&progress](int done, int total, double) {
    progress.update(std::size_t(done), std::size_t(total));
  };
  if (euroc) {
    options.prepare_pair = [&raw](cv::Mat& left, cv::Mat& right) {
      raw.rectification.apply(left, right);
    };
  }
  result.run = vo::run_stereo_vo(sequence, config, options);
  progress.finish();
  const vo::SequenceRun& run = result.run;

  std::filesystem::create_directories(a.out);
  io::write_sodso_poses(a.out + "/poses_history_file.txt", run.keyframe_poses);
  io::write_sodso_points(a.out + "/pts_history_file.txt", run.points);
  std::vector<Eigen::Matrix<double, 3, 4>> trajectory;
  for (const Eigen::Isometry3d& T : run.trajectory) trajectory.push_back(T.matrix().topRows<3>());
  io::write_kitti_poses(a.out + "/trajectory.txt", trajectory);
  // TUM: the camera for KITTI layouts, the body (T_BS's frame) for EuRoC, as its ground truth.
  std::vector<double> times;
  std::vector<Eigen::Isometry3d> tum;
  const Eigen::Isometry3d camera_to_body =
      euroc ? raw.rectification.T_body_rectified.inverse() : Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < run.frame_ids.size(); ++i) {
    times.push_back(sequence.times[static_cast<std::size_t>(run.frame_ids[i])]);
    tum.push_back(run.trajectory[i] * camera_to_body);
  }
  io::write_tum_trajectory(a.out + "/trajectory_tum.txt", times, tum);

  const vo::StageTimes& s = run.stage_ms;
  nlohmann::json& j = result.summary;
  j = {{"sequence", euroc ? a.euroc : a.kitti},
       {"layout", euroc ? "euroc" : "kitti"},
       {"first_frame", run.frame_ids.empty() ? 0 : run.frame_ids.front()},
       {"frames", run.frame_ids.size()},
       {"keyframes", run.keyframes.size()},
       {"reset_frames", run.reset_frames},
       {"mean_points_per_keyframe", run.mean_points_per_keyframe},
       {"seconds", run.seconds},
       {"fps", run.fps},
       {"ms_per_frame",
        {{"load_images", run.load_ms},
         {"track", s.track},
         {"pose", s.pose},
         {"keyframe", s.keyframe},
         {"bundle_adjustment", s.bundle_adjustment},
         {"export_points", s.export_points}}},
       {"camera",
        {{"fx", run.camera.fx},
         {"fy", run.camera.fy},
         {"cx", run.camera.cx},
         {"cy", run.camera.cy},
         {"baseline_m", run.camera.baseline_m},
         {"width", run.camera.width},
         {"height", run.camera.height}}},
       {"points_per_keyframe_target", config.points_per_keyframe}};
  std::printf(
      "VO: %zu frames of %dx%d, %zu keyframes, %zu resets, %.1f fps (ms per frame: load %.1f on "
      "the reader thread, track %.1f, pose %.1f, keyframe %.1f, BA %.1f, points %.1f); %.0f "
      "points per keyframe\n",
      run.frame_ids.size(), run.camera.width, run.camera.height, run.keyframes.size(),
      run.reset_frames.size(), run.fps, run.load_ms, s.track, s.pose, s.keyframe,
      s.bundle_adjustment, s.export_points, run.mean_points_per_keyframe);
  if (!gt_rows.empty() && run.frame_ids.size() >= 2) {
    std::vector<Eigen::Isometry3d> gt;
    for (int f : run.frame_ids) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.matrix().topRows<3>() = gt_rows[static_cast<std::size_t>(f)];
      gt.push_back(T);
    }
    const eval::OdometryMetrics m =
        eval::odometry_metrics(gt, run.trajectory, c.odometry_metrics.kitti);
    j["ground_truth"] = result.gt_path;
    j["metrics"] = metrics_json(m);
    if (m.segments > 0) {
      std::printf("KITTI metrics over %d segments: translation %.2f %%, rotation %.3f deg/100 m; ",
                  m.segments, m.translation_percent, m.rotation_deg_per_100m);
    } else {
      std::printf("KITTI metrics: no segment fits a %.0f m path (set "
                  "odometry_metrics.segment_lengths_m); ",
                  m.path_length_m);
    }
    std::printf(
        "ATE %.3f m (%.3f m after Sim(3) alignment, scale %.4f), end point %.2f %% of "
        "%.0f m\n",
        m.ate_rmse_m, m.ate_sim3_rmse_m, m.sim3_scale, m.end_point_error_percent, m.path_length_m);
  }
  if (euroc && !a.gt.empty()) {
    const double rpe_delta_m = c.odometry_metrics.rpe_delta_m;
    j["metrics"] = tum_metrics(times, tum, tum_gt, a.gt, rpe_delta_m);
    const nlohmann::json& m = j["metrics"];
    std::printf(
        "against %s (%d frames matched, SE(3)-aligned): ATE %.3f m = %.2f %% of %.2f m (%.3f m "
        "after Sim(3) alignment, scale %.4f); RPE over %.2f m: %.3f m, %.2f deg (%d pairs)\n",
        a.gt.c_str(), m["matched_frames"].get<int>(), m["ate_rmse_m"].get<double>(),
        m["ate_percent_of_path"].get<double>(), m["path_length_m"].get<double>(),
        m["ate_sim3_rmse_m"].get<double>(), m["sim3_scale"].get<double>(), rpe_delta_m,
        m["rpe_translation_rmse_m"].get<double>(), m["rpe_rotation_rmse_deg"].get<double>(),
        m["rpe_pairs"].get<int>());
  }
  io::write_file_atomic(a.out + "/vo.json", j.dump(1) + "\n");
  write_used_configuration(a.out, c);
  return result;
}

}  // namespace loopscan::cli
