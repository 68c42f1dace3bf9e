#include "outputs/closure.hpp"

#include "cli/configuration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "cli/progress.hpp"
#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/eval/loop_metrics.hpp"
#include "loopscan/eval/odometry_metrics.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/database_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/text_file_writer.hpp"
#include "loopscan/io/vo_files.hpp"
#include "outputs/closure_figures.hpp"

namespace loopscan::cli {
namespace {

Eigen::Isometry3d world_cam(const KeyframePose& k) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = k.T_cam_world.leftCols<3>();
  T.translation() = k.T_cam_world.col(3);
  return T.inverse();
}

Eigen::Isometry3d gt_pose(const GroundTruth& gt, int id) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix().topRows<3>() = gt.poses[std::size_t(id)];
  return T;
}

double mean_ms(double total, int count) { return count > 0 ? total / count : 0.0; }

struct Recall {
  int revisits = 0, closed = 0;
};

// Described keyframes of this session with a true revisit (a place of another session, or of
// this one added at least 100 places earlier, within `within_m`), and those of them that got
// a true accepted loop.
Recall revisit_recall(const ClosureRun& run, const GroundTruth& gt, const GroundTruth& map_gt,
                      double within_m, const std::set<int>& closed) {
  std::vector<Eigen::Vector3d> mine, others;
  std::vector<int> mine_ids;
  for (std::size_t i = 0; i < run.map.size(); ++i) {
    const PlaceRef p = run.map.place(i);
    const GroundTruth& g = p.session == run.session ? gt : map_gt;
    if (p.keyframe < 0 || std::size_t(p.keyframe) >= g.positions.size()) continue;
    if (p.session == run.session) {
      mine.push_back(g.positions[std::size_t(p.keyframe)]);
      mine_ids.push_back(p.keyframe);
    } else {
      others.push_back(g.positions[std::size_t(p.keyframe)]);
    }
  }
  Recall r;
  const double w2 = within_m * within_m;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    bool revisit = false;
    for (std::size_t j = 0; j < others.size() && !revisit; ++j)
      revisit = (mine[i] - others[j]).squaredNorm() <= w2;
    for (std::size_t j = 0; j + 100 <= i && !revisit; ++j)
      revisit = (mine[i] - mine[j]).squaredNorm() <= w2;
    r.revisits += revisit;
    r.closed += revisit && closed.count(mine_ids[i]);
  }
  return r;
}

}  // namespace

std::vector<Eigen::Vector3d> positions(const std::vector<KeyframePose>& poses) {
  std::vector<Eigen::Vector3d> out;
  for (const KeyframePose& k : poses) out.push_back(world_cam(k).translation());
  return out;
}

ClosureRun run_closer(const closure::LoopCloserConfig& config,
                      const std::vector<KeyframePose>& poses, const std::vector<IdPoint>& points,
                      const std::vector<int>& reset_ids, bool progress, SavedMap* map) {
  const auto t0 = std::chrono::steady_clock::now();
  closure::LoopCloser closer =
      map ? closure::LoopCloser(config, std::move(map->places), std::move(map->clouds))
          : closure::LoopCloser(config);
  std::vector<int> resets = reset_ids;
  std::sort(resets.begin(), resets.end());
  int accepted = 0;
  std::size_t done = 0;
  StepProgress bar("close loops", "keyframes", !progress);
  for_each_keyframe(poses, points, [&](const KeyframePose& k, const IdPoint* first, std::size_t n) {
    const bool reset = std::binary_search(resets.begin(), resets.end(), k.id);
    accepted += int(closer.add_keyframe(k, first, n, reset).accepted.size());
    bar.update(++done, poses.size());
  });
  bar.finish(", " + std::to_string(accepted) + " loops accepted");
  closer.finish();
  ClosureRun run;
  run.input = poses;
  run.closed = closer.corrected_poses();
  run.loops = closer.loops();
  run.times = closer.times();
  run.described = closer.times().described;
  run.session = config.recognition.session;
  run.anchored = closer.anchored();
  run.anchored_at = closer.anchored_at();
  run.map = closer.corrected_map();
  run.clouds = closer.place_clouds();
  run.total_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

GroundTruth read_ground_truth(const std::string& path, const std::vector<KeyframePose>& poses) {
  GroundTruth gt;
  gt.path = path;
  if (io::detect_gt_format(path) == io::GtFormat::Kitti) {
    gt.poses = io::read_kitti_poses(path);
    for (const auto& T : gt.poses) gt.positions.push_back(T.col(3));
  } else {
    gt.positions = io::read_positions(path, io::GtFormat::RobotCar);
  }
  for (const KeyframePose& k : poses) {
    if (k.id < 0 || std::size_t(k.id) >= gt.positions.size()) {
      throw io::InputError(path, 0,
                           "a line for keyframe id " + std::to_string(k.id) + " (file has " +
                               std::to_string(gt.positions.size()) + " lines)");
    }
  }
  return gt;
}

ClosureOutputs write_closure_outputs(const std::string& dir, const ClosureRun& run,
                                     const Configuration& c, const std::optional<GroundTruth>& gt,
                                     const std::optional<GroundTruth>& map_gt) {
  const double true_within_m = c.closure.true_within_m;
  write_used_configuration(dir, c);
  io::save_database(run.map, dir + "/map.db", &run.clouds);
  std::error_code ec;
  const double map_bytes = double(std::filesystem::file_size(dir + "/map.db", ec));
  io::write_sodso_poses(dir + "/poses_closed.txt", run.closed);
  std::vector<Eigen::Matrix<double, 3, 4>> kitti;
  for (const KeyframePose& k : run.closed) kitti.push_back(world_cam(k).matrix().topRows<3>());
  io::write_kitti_poses(dir + "/trajectory_closed.txt", kitti);

  // loops.csv, with the truth of each loop when there is ground truth.
  std::vector<char> loop_true;
  int proposed = 0, accepted = 0, true_accepted = 0;
  std::vector<double> t_err, r_err;
  std::set<int> accepted_queries;  // with a true accepted loop
  io::TextFileWriter csv(dir + "/loops.csv");
  csv.write(std::string("query,match,session,r00,r01,r02,tx,r10,r11,r12,ty,r20,r21,r22,tz,") +
            "overlap,rmse,accepted,verdict,distance,constraint,source" +
            (gt ? ",true,gt_distance,translation_error,"
                  "rotation_error_deg"
                : "") +
            "\n");
  for (const closure::Loop& l : run.loops) {
    ++proposed;
    accepted += l.accepted();
    char line[1024];
    const Eigen::Matrix4d& M = l.T_query_match.matrix();
    int n =
        std::snprintf(line, sizeof line, "%d,%d,%d", l.query, l.match.keyframe, l.match.session);
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 4; ++k) n += std::snprintf(line + n, sizeof line - n, ",%.9g", M(r, k));
    }
    n += std::snprintf(line + n, sizeof line - n, ",%.4f,%.4f,%d,%s,%.6g,%.5f", l.overlap, l.rmse_m,
                       int(l.accepted()), closure::to_string(l.verdict), l.distance,
                       l.translation_constraint);
    n += std::snprintf(line + n, sizeof line - n, ",%s", l.nearby ? "nearby" : "descriptor");
    if (gt) {
      const GroundTruth& other = l.match.session != run.session && map_gt ? *map_gt : *gt;
      if (l.match.keyframe < 0 || std::size_t(l.match.keyframe) >= other.positions.size()) {
        throw io::InputError(other.path, 0,
                             "a line for map keyframe id " + std::to_string(l.match.keyframe));
      }
      eval::LoopTruth t;
      if (!gt->poses.empty() && !other.poses.empty()) {
        t = eval::loop_truth(l.T_query_match, gt_pose(*gt, l.query),
                             gt_pose(other, l.match.keyframe), true_within_m);
      } else {
        t.gt_distance_m =
            (gt->positions[std::size_t(l.query)] - other.positions[std::size_t(l.match.keyframe)])
                .norm();
        t.is_true = t.gt_distance_m <= true_within_m;
        t.translation_error_m = std::abs(l.T_query_match.translation().norm() - t.gt_distance_m);
        t.rotation_error_deg = NAN;
      }
      loop_true.push_back(t.is_true);
      if (l.accepted()) {
        if (t.is_true) accepted_queries.insert(l.query);
        true_accepted += t.is_true;
        if (t.is_true)
          t_err.push_back(t.translation_error_m), r_err.push_back(t.rotation_error_deg);
      }
      n += std::snprintf(line + n, sizeof line - n, ",%d,%.4f,%.4f,%.4f", int(t.is_true),
                         t.gt_distance_m, t.translation_error_m, t.rotation_error_deg);
    }
    csv.write(std::string(line, std::size_t(n)) + "\n");
  }
  csv.commit();

  const closure::StageTimes& tm = run.times;
  nlohmann::json m = {{"method", method_name(c.method)},
                      {"keyframes", run.input.size()},
                      {"described", run.described},
                      {"loops", {{"proposed", proposed}, {"accepted", accepted}}},
                      {"ms_per_keyframe",
                       {{"scan", mean_ms(tm.scan, tm.keyframes)},
                        {"describe", mean_ms(tm.describe, tm.described)},
                        {"cloud", mean_ms(tm.cloud, tm.described)},
                        {"query", mean_ms(tm.query, tm.described)},
                        {"verify", mean_ms(tm.verify, tm.described)},
                        {"graph", mean_ms(tm.graph, tm.keyframes)},
                        {"total", mean_ms(run.total_ms, tm.keyframes)}}},
                      {"ms_per_verification", mean_ms(tm.verify, tm.verifications)},
                      {"ms_per_solve", mean_ms(tm.graph, tm.solves)},
                      {"solves", tm.solves},
                      {"session", run.session},
                      {"anchored_to_map", run.anchored},
                      {"anchored_at_keyframe", run.anchored_at},
                      {"map_places", run.map.size()},
                      {"map_bytes_per_place",
                       run.map.size() > 0 && !ec ? map_bytes / double(run.map.size()) : 0.0}};
  if (gt) {
    std::vector<Eigen::Vector3d> ref;
    for (const KeyframePose& k : run.input) ref.push_back(gt->positions[std::size_t(k.id)]);
    m["ground_truth"] = gt->path;
    m["true_within_m"] = true_within_m;
    m["ate_before_m"] = eval::aligned_rmse(ref, positions(run.input));
    m["ate_after_m"] = eval::aligned_rmse(ref, positions(run.closed));
    m["loops"]["true_accepted"] = true_accepted;
    m["loops"]["false_accepted"] = accepted - true_accepted;
    m["loops"]["precision"] = accepted > 0 ? double(true_accepted) / accepted : 1.0;
    const Recall r =
        revisit_recall(run, *gt, map_gt ? *map_gt : *gt, true_within_m, accepted_queries);
    m["loops"]["revisit_keyframes"] = r.revisits;
    m["loops"]["revisits_closed"] = r.closed;
    m["loops"]["recall"] = r.revisits > 0 ? double(r.closed) / r.revisits : 0.0;
    const auto median = [](std::vector<double> v) {
      if (v.empty()) return std::nan("");
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    m["loops"]["median_translation_error_m"] = median(t_err);
    m["loops"]["median_rotation_error_deg"] = median(r_err);
    if (!gt->poses.empty()) {
      std::vector<Eigen::Isometry3d> g, before, after;
      for (std::size_t i = 0; i < run.input.size(); ++i) {
        g.push_back(gt_pose(*gt, run.input[i].id));
        before.push_back(world_cam(run.input[i]));
        after.push_back(world_cam(run.closed[i]));
      }
      const eval::RelativeError rb = eval::relative_pose_error(g, before, 10.0);
      const eval::RelativeError ra = eval::relative_pose_error(g, after, 10.0);
      m["rpe10m_before"] = {{"translation_rmse_m", rb.translation_rmse_m},
                            {"rotation_rmse_deg", rb.rotation_rmse_deg}};
      m["rpe10m_after"] = {{"translation_rmse_m", ra.translation_rmse_m},
                           {"rotation_rmse_deg", ra.rotation_rmse_deg}};
      // KITTI's drift measure (100..800 m segments) of the keyframe trajectory.
      const eval::OdometryMetrics kb = eval::odometry_metrics(g, before);
      const eval::OdometryMetrics ka = eval::odometry_metrics(g, after);
      m["kitti_drift_before"] = {{"translation_percent", kb.translation_percent},
                                 {"rotation_deg_per_100m", kb.rotation_deg_per_100m}};
      m["kitti_drift_after"] = {{"translation_percent", ka.translation_percent},
                                {"rotation_deg_per_100m", ka.rotation_deg_per_100m}};
    }
  }
  const ClosureFigures figures = closure_figures(run, gt, loop_true);
  io::write_file_atomic(dir + "/trajectory.svg", figures.map);
  if (!figures.error.empty()) io::write_file_atomic(dir + "/error.svg", figures.error);
  io::write_file_atomic(dir + "/metrics.json", m.dump(1) + "\n");
  return {m, figures};
}

ClosureOutputs close_vo_run(const std::string& dir, const std::vector<KeyframePose>& poses,
                            const std::vector<IdPoint>& points, const std::vector<int>& resets,
                            const std::optional<GroundTruth>& gt, const Configuration& c,
                            bool progress) {
  std::filesystem::create_directories(dir);
  return write_closure_outputs(
      dir, run_closer(loop_closer_config(c), poses, points, resets, progress), c, gt, {});
}

}  // namespace loopscan::cli
