#include "outputs/closure.hpp"

#include "cli/configuration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

#include <sys/resource.h>

#include "cli/progress.hpp"
#include "loopscan/closure/background_closer.hpp"
#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/eval/latency.hpp"
#include "loopscan/eval/loop_metrics.hpp"
#include "loopscan/eval/odometry_metrics.hpp"
#include "loopscan/eval/protocol.hpp"
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

// The process's peak resident memory so far (what `close` needed, its input included).
double peak_resident_mb() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

// A keyframe of this session paired with a place of the run's map: a true revisit and its
// nearest place, or an accepted loop and its place.
struct KeyframePlace {
  int keyframe = 0;
  std::size_t place = 0;  // index into the run's map
};

// The described keyframes of this session with a true revisit: a place of another session, or
// of this one described at least 100 keyframes earlier, within `within_m` (the evaluation
// protocol's ground truth), each paired with the nearest one. Keyframes that linked to a held
// place instead of joining the map are revisits too, but never partners.
std::vector<KeyframePlace> true_revisits(const ClosureRun& run, const GroundTruth& gt,
                                         const GroundTruth& map_gt, double within_m) {
  const Eigen::Vector3d absent = Eigen::Vector3d::Constant(std::nan(""));
  std::unordered_map<int, std::size_t> described_at;  // keyframe id -> described order
  std::vector<Eigen::Vector3d> mine, mine_in_map, others;
  std::vector<int> mine_ids;
  for (int id : run.described_ids) {
    if (id < 0 || std::size_t(id) >= gt.positions.size()) continue;
    described_at[id] = mine.size();
    mine.push_back(gt.positions[std::size_t(id)]);
    mine_ids.push_back(id);
  }
  mine_in_map.assign(mine.size(), absent);  // non-finite: never a partner
  std::vector<std::size_t> map_index_of(mine.size(), 0), others_index;
  for (std::size_t i = 0; i < run.map.size(); ++i) {
    const PlaceRef p = run.map.place(i);
    if (p.session == run.session) {
      const auto it = described_at.find(p.keyframe);
      if (it == described_at.end()) continue;
      mine_in_map[it->second] = mine[it->second];
      map_index_of[it->second] = i;
    } else if (p.keyframe >= 0 && std::size_t(p.keyframe) < map_gt.positions.size()) {
      others.push_back(map_gt.positions[std::size_t(p.keyframe)]);
      others_index.push_back(i);
    }
  }
  const eval::GroundTruth earlier =
      eval::compute_ground_truth(mine, mine_in_map, {within_m, 100, true});
  const eval::GroundTruth elsewhere = eval::compute_ground_truth(mine, others, {within_m, 0});
  std::vector<KeyframePlace> out;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    const auto d2 = [&](const Eigen::Vector3d& p) { return (mine[i] - p).squaredNorm(); };
    const int e = earlier.is_loop[i] ? earlier.nearest[i] : -1;
    const int o = elsewhere.is_loop[i] ? elsewhere.nearest[i] : -1;
    if (e < 0 && o < 0) continue;
    const bool cross = o >= 0 && (e < 0 || d2(others[std::size_t(o)]) < d2(mine[std::size_t(e)]));
    out.push_back(
        {mine_ids[i], cross ? others_index[std::size_t(o)] : map_index_of[std::size_t(e)]});
  }
  return out;
}

// What loops could give: the pose graph of `config` over the VO's keyframes (orthonormalised
// as the closer takes them), given a loop per pair (every true revisit, or the closer's own
// loops) with its ground-truth relative pose at 0.1 m and 0.5 degrees; the trajectory's ATE
// after the solve. Places of a saved map are fixed at their map poses. NaN without
// ground-truth orientations (RobotCar GPS).
double ate_given_true_loops(const ClosureRun& run, const GroundTruth& gt, const GroundTruth& map_gt,
                            const std::vector<KeyframePlace>& pairs,
                            closure::PoseGraphConfig config) {
  if (gt.poses.empty() || map_gt.poses.empty() || run.input.empty()) return std::nan("");
  config.loop_translation_m = 0.1;
  config.loop_rotation_deg = 0.5;
  closure::PoseGraph graph(config);
  std::map<int, int> node_of;  // keyframe id -> node
  Eigen::Isometry3d previous = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < run.input.size(); ++i) {
    const Eigen::Isometry3d T = world_cam(closure::orthonormalised(run.input[i]));
    const bool reset = std::binary_search(run.resets.begin(), run.resets.end(), run.input[i].id);
    const Eigen::Isometry3d odometry = previous.inverse() * T;
    node_of[run.input[i].id] = graph.add_node(T, i == 0 || reset ? nullptr : &odometry);
    previous = T;
  }
  bool in_map_frame = false;
  std::map<std::size_t, int> fixed_node;  // map place -> node
  for (const KeyframePlace& r : pairs) {
    const PlaceRef p = run.map.place(r.place);
    const bool own = p.session == run.session;
    const Eigen::Isometry3d T_query_match =
        gt_pose(gt, r.keyframe).inverse() * gt_pose(own ? gt : map_gt, p.keyframe);
    const int a = node_of.at(r.keyframe);
    int b;
    if (own) {
      b = node_of.at(p.keyframe);
    } else if (const auto it = fixed_node.find(r.place); it != fixed_node.end()) {
      b = it->second;
    } else {
      KeyframePose place;
      place.T_cam_world = *run.map.pose(r.place);
      const Eigen::Isometry3d T_map_match = world_cam(closure::orthonormalised(place));
      if (!in_map_frame) {  // start the session in the map's frame, as the closer's anchoring
        graph.transform(T_map_match * T_query_match.inverse() * graph.pose(a).inverse());
        in_map_frame = true;
      }
      b = fixed_node[r.place] = graph.add_fixed_node(T_map_match);
    }
    graph.add_loop_unsolved(a, b, T_query_match);
  }
  graph.optimise();
  std::vector<Eigen::Vector3d> ref, after;
  for (const KeyframePose& k : run.input) {
    ref.push_back(gt.positions[std::size_t(k.id)]);
    after.push_back(graph.position(node_of.at(k.id)));
  }
  return eval::aligned_rmse(ref, after);
}

}  // namespace

std::vector<Eigen::Vector3d> positions(const std::vector<KeyframePose>& poses) {
  std::vector<Eigen::Vector3d> out;
  for (const KeyframePose& k : poses) out.push_back(world_cam(k).translation());
  return out;
}

int closure_queue(const Configuration& c) {
  return c.closure.background ? c.closure.queue_capacity : 0;
}

namespace {

template <typename Closer>
void replay(Closer& closer, const std::vector<KeyframePose>& poses, const KeyframePoints& points,
            const std::vector<int>& resets, bool progress, ClosureRun& run) {
  int accepted = 0;
  std::size_t done = 0;
  StepProgress bar("close loops", "keyframes", !progress);
  const auto count = [&](const closure::KeyframeClosure& closed) {
    accepted += int(closed.accepted.size());
  };
  for (const KeyframePose& k : poses) {
    const auto [first, n] = points(k.id);
    const bool reset = std::binary_search(resets.begin(), resets.end(), k.id);
    const auto start = std::chrono::steady_clock::now();
    const closure::KeyframeClosure result = closer.add_keyframe(k, first, n, reset);
    double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if constexpr (std::is_same_v<Closer, closure::BackgroundLoopCloser>) {
      ms -= closer.queue().last_wait_ms;
      for (const closure::KeyframeClosure& closed : closer.poll()) count(closed);
    } else {
      count(result);
    }
    if (result.described) run.described_ids.push_back(k.id);
    run.add_keyframe_ms.push_back(ms);
    bar.update(++done, poses.size());
  }
  closer.finish();
  if constexpr (std::is_same_v<Closer, closure::BackgroundLoopCloser>) {
    for (const closure::KeyframeClosure& closed : closer.poll()) count(closed);
    const closure::QueueStats q = closer.queue();
    run.queue_waits = q.waits;
    run.queue_wait_ms = q.waited_ms;
    run.background = true;
  }
  bar.finish(", " + std::to_string(accepted) + " loops accepted");
  run.closed = closer.corrected_poses();
  run.loops = closer.loops();
  run.times = closer.times();
  run.described = run.times.described;
  run.anchored = closer.anchored();
  run.anchored_at = closer.anchored_at();
  run.map = closer.corrected_map();
  const auto t0 = std::chrono::steady_clock::now();
  run.clouds = closer.place_clouds();
  run.clouds_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

KeyframePoints points_in_memory(const std::vector<IdPoint>& points) {
  return [&points, next = std::size_t(0)](int keyframe_id) mutable {
    const std::size_t first = next;
    while (next < points.size() && points[next].id <= keyframe_id) ++next;
    return std::pair<const IdPoint*, std::size_t>(points.data() + first, next - first);
  };
}

ClosureRun run_closer(const closure::LoopCloserConfig& config,
                      const std::vector<KeyframePose>& poses, const KeyframePoints& points,
                      const std::vector<int>& reset_ids, bool progress, int background_queue,
                      SavedMap* map) {
  const auto t0 = std::chrono::steady_clock::now();
  ClosureRun run;
  run.input = poses;
  run.resets = reset_ids;
  std::sort(run.resets.begin(), run.resets.end());
  run.session = config.recognition.session;
  Database places = map ? std::move(map->places) : Database(map_config(config.recognition));
  std::vector<PlaceCloud> clouds = map ? std::move(map->clouds) : std::vector<PlaceCloud>{};
  if (background_queue > 0) {
    closure::BackgroundConfig background;
    background.queue_capacity = background_queue;
    background.when_full = closure::BackgroundConfig::WhenFull::Wait;
    closure::BackgroundLoopCloser closer(config, std::move(places), std::move(clouds), background);
    replay(closer, poses, points, run.resets, progress, run);
  } else {
    closure::LoopCloser closer(config, std::move(places), std::move(clouds));
    replay(closer, poses, points, run.resets, progress, run);
  }
  run.total_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  run.peak_memory_mb = peak_resident_mb();
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
  std::vector<KeyframePlace> accepted_pairs;  // the true accepted loops
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
      if (l.accepted() && t.is_true) {
        ++true_accepted;
        t_err.push_back(t.translation_error_m);
        r_err.push_back(t.rotation_error_deg);
        const PlaceRef at = run.map.place(l.place_index);
        if (at.session != l.match.session || at.keyframe != l.match.keyframe) {
          throw std::logic_error("close: a loop's place index is not its place in the map");
        }
        accepted_pairs.push_back({l.query, l.place_index});
      }
      n += std::snprintf(line + n, sizeof line - n, ",%d,%.4f,%.4f,%.4f", int(t.is_true),
                         t.gt_distance_m, t.translation_error_m, t.rotation_error_deg);
    }
    csv.write(std::string(line, std::size_t(n)) + "\n");
  }
  csv.commit();

  const closure::StageTimes& tm = run.times;
  const closure::StageMeans ms = closure::stage_means(tm);
  const eval::LatencySummary latency = eval::summarise_latency(run.add_keyframe_ms);
  nlohmann::json m = {{"method", method_name(c.method)},
                      {"keyframes", run.input.size()},
                      {"described", run.described},
                      {"loops", {{"proposed", proposed}, {"accepted", accepted}}},
                      {"ms_per_keyframe",
                       {{"scan", ms.scan},
                        {"describe", ms.describe},
                        {"cloud", ms.cloud},
                        {"query", ms.query},
                        {"verify", ms.verify},
                        {"graph", ms.graph},
                        {"total", tm.keyframes > 0 ? run.total_ms / tm.keyframes : 0.0}}},
                      {"ms_per_verification", ms.per_verification},
                      {"ms_per_solve", ms.per_solve},
                      {"solves", tm.solves},
                      {"session", run.session},
                      {"anchored_to_map", run.anchored},
                      {"anchored_at_keyframe", run.anchored_at},
                      {"add_keyframe_latency_ms",
                       {{"p50", latency.p50_ms}, {"p99", latency.p99_ms}, {"max", latency.max_ms}}},
                      {"peak_memory_mb", run.peak_memory_mb},
                      {"background", run.background},
                      {"threads", c.closure.closer.threads},
                      {"map_clouds_ms", run.clouds_ms},
                      {"queue_waits", {{"count", run.queue_waits}, {"ms", run.queue_wait_ms}}},
                      {"map_places", run.map.size()},
                      {"linked_keyframes", tm.linked},
                      {"graph", {{"nodes", tm.graph_nodes}, {"edges", tm.graph_edges}}},
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
    const GroundTruth& others = map_gt ? *map_gt : *gt;
    const std::vector<KeyframePlace> revisits = true_revisits(run, *gt, others, true_within_m);
    std::set<int> closed_keyframes;
    for (const KeyframePlace& p : accepted_pairs) closed_keyframes.insert(p.keyframe);
    int closed = 0;
    for (const KeyframePlace& r : revisits) closed += closed_keyframes.count(r.keyframe) > 0;
    m["loops"]["revisit_keyframes"] = revisits.size();
    m["loops"]["revisits_closed"] = closed;
    m["loops"]["recall"] = revisits.empty() ? 0.0 : double(closed) / double(revisits.size());
    const closure::PoseGraphConfig graph = loop_closer_config(c).graph;
    const double reachable = ate_given_true_loops(run, *gt, others, revisits, graph);
    if (reachable == reachable) m["ate_given_true_loops_m"] = reachable;
    // The accepted true loops made exact (their own pairs, ground-truth relative poses): against
    // ate_after_m what the loops' errors cost, against ate_given_true_loops_m what the missed
    // revisits cost.
    const double exact = ate_given_true_loops(run, *gt, others, accepted_pairs, graph);
    if (exact == exact) m["ate_given_exact_accepted_loops_m"] = exact;
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
  return write_closure_outputs(dir,
                               run_closer(loop_closer_config(c), poses, points_in_memory(points),
                                          resets, progress, closure_queue(c)),
                               c, gt, {});
}

}  // namespace loopscan::cli
