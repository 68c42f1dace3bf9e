// loopscan close: a VO's SO-DSO export -> verified loops, a pose graph, the corrected
// trajectory (poses_closed.txt, trajectory_closed.txt), loops.csv, metrics.json, trajectory.svg.
#include <algorithm>
#include <cstdio>

#include "closure_outputs.hpp"
#include "commands.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/io/database_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/sodso.hpp"
#include "loopscan/io/vo_files.hpp"
#include "options.hpp"
#include "output_sets.hpp"

namespace loopscan::cli {
namespace {

struct CloseArgs {
  std::string poses, points, out, gt, gt_format = "kitti", method = "sc", mode = "default",
                                      reset_ids, map, map_gt;
  double range_m = 45.0, true_within_m = 10.0;
  bool write_points = false, quiet = false;
  closure::LoopCloserConfig config;
};

void run_close(const CloseArgs& a) {
  const Method method = parse_method(a.method);
  const Mode mode = parse_mode(a.mode);
  closure::LoopCloserConfig config = closure::LoopCloserConfig::make(method, mode, a.range_m);
  config.candidates = a.config.candidates;
  config.verify.min_overlap = a.config.verify.min_overlap;
  config.consistency.required = a.config.consistency.required;
  config.graph.odometry_translation_per_m = a.config.graph.odometry_translation_per_m;
  config.graph.odometry_rotation_deg_per_m = a.config.graph.odometry_rotation_deg_per_m;
  const std::vector<KeyframePose> poses = io::read_sodso_poses(a.poses);
  const std::vector<IdPoint> points = io::read_sodso_points(a.points);
  std::optional<GroundTruth> gt;
  if (!a.gt.empty()) gt = read_ground_truth(a.gt, a.gt_format, poses);
  const std::vector<int> resets = !a.reset_ids.empty()    ? io::read_incoming_ids(a.reset_ids)
                                  : mode == Mode::Default ? detect_vo_resets(poses)
                                                          : std::vector<int>{};
  std::optional<SavedMap> map;
  if (!a.map.empty()) {
    map.emplace();
    map->places = io::load_database(a.map, &config.recognition.database, &map->clouds);
    if (map->clouds.empty() && map->places.size() > 0) {
      throw io::InputError(a.map, 0,
                           "place clouds (this map was saved without them: build it "
                           "with `loopscan close`)");
    }
    for (std::size_t i = 0; i < map->places.size(); ++i) {
      config.recognition.session =
          std::max(config.recognition.session, map->places.place(i).session + 1);
    }
  }
  std::optional<GroundTruth> map_gt;
  if (!a.map_gt.empty()) map_gt = read_ground_truth(a.map_gt, a.gt_format, {});
  const ClosureRun run = run_closer(config, poses, points, resets, !a.quiet, map ? &*map : nullptr);
  const nlohmann::json m =
      write_closure_outputs(a.out, run, config, gt, map_gt, a.true_within_m).metrics;
  if (a.write_points) {
    io::write_sodso_points(a.out + "/pts_closed.txt",
                           closure::reexpress_points(points, run.input, run.closed));
  }
  std::printf("%s: %zu keyframes, %d described; loops: %d proposed, %d accepted",
              method_name(method).c_str(), poses.size(), run.described,
              m["loops"]["proposed"].get<int>(), m["loops"]["accepted"].get<int>());
  if (gt) std::printf(" (%d false)", m["loops"]["false_accepted"].get<int>());
  if (map && run.anchored) std::printf("; in the map's frame from keyframe %d", run.anchored_at);
  if (map && !run.anchored) std::printf("; not localised in the map");
  if (gt) {
    std::printf("; ATE %.3f m -> %.3f m", m["ate_before_m"].get<double>(),
                m["ate_after_m"].get<double>());
  }
  std::printf("; %.2f ms per keyframe -> %s\n", m["ms_per_keyframe"]["total"].get<double>(),
              shown(a.out).c_str());
}

}  // namespace

void add_close_command(CLI::App& app) {
  auto a = std::make_shared<CloseArgs>();
  CLI::App* cmd = app.add_subcommand(
      "close", "Close loops in a VO's SO-DSO export: verified loops and a corrected trajectory");
  cmd->add_option("--poses", a->poses, "SO-DSO poses_history_file.txt")->required();
  cmd->add_option("--points", a->points, "SO-DSO pts_history_file.txt (or .gz)")->required();
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--gt", a->gt, "ground truth (one line per frame id) for the metrics");
  cmd->add_option("--gt-format", a->gt_format, "kitti | robotcar")->capture_default_str();
  cmd->add_option("--method", a->method, "place recognition: sc | m2dp | delight")
      ->capture_default_str();
  cmd->add_option("--mode", a->mode, "reference | default")->capture_default_str();
  cmd->add_option("--range", a->range_m, "imitated LiDAR range in m")
      ->check(finite_in(0.1, 1000))
      ->capture_default_str();
  cmd->add_option("--reset-ids", a->reset_ids, "file of keyframe ids where the VO reset");
  cmd->add_option("--map", a->map,
                  "a saved map (another session's map.db): localise in it and extend it");
  cmd->add_option("--map-gt", a->map_gt,
                  "ground truth of the map's keyframes when it is not --gt's trajectory");
  cmd->add_option("--candidates", a->config.candidates, "places verified per keyframe")
      ->check(finite_in(1, 100))
      ->capture_default_str();
  cmd->add_option("--min-overlap", a->config.verify.min_overlap,
                  "verification: share of the place's structure points the query must cover")
      ->check(finite_in(0, 1))
      ->capture_default_str();
  cmd->add_option("--consistent", a->config.consistency.required,
                  "verified loops of nearby keyframes that must agree before one is accepted")
      ->check(finite_in(1, 100))
      ->capture_default_str();
  cmd->add_option("--odometry-sigma", a->config.graph.odometry_translation_per_m,
                  "pose graph: VO translation uncertainty, m per m travelled")
      ->check(finite_in(1e-6, 1))
      ->capture_default_str();
  cmd->add_option("--odometry-sigma-rotation", a->config.graph.odometry_rotation_deg_per_m,
                  "pose graph: VO rotation uncertainty, deg per m travelled")
      ->check(finite_in(1e-6, 90))
      ->capture_default_str();
  cmd->add_option("--true-within", a->true_within_m,
                  "with --gt: a loop is true when its keyframes are this close (m)")
      ->check(finite_in(0.01, 1000))
      ->capture_default_str();
  cmd->add_flag("--write-points", a->write_points,
                "also write pts_closed.txt: the points re-expressed with the corrected poses");
  cmd->add_flag("--quiet", a->quiet, "no progress line");
  run_writing_dir(cmd, a, run_close);
}

}  // namespace loopscan::cli
