// loopscan close: a VO's SO-DSO export -> verified loops, a pose graph, the corrected
// trajectory (poses_closed.txt, trajectory_closed.txt), loops.csv, metrics.json, trajectory.svg.
#include <algorithm>
#include <cstdio>
#include <limits>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/io/database_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/sodso.hpp"
#include "loopscan/io/vo_files.hpp"
#include "outputs/closure.hpp"

namespace loopscan::cli {
namespace {

struct CloseArgs {
  ConfigFlags config;
  std::string poses, points, out, gt, reset_ids, map, map_gt;
  bool write_points = false, quiet = false;
};

void run_close(const CloseArgs& a) {
  // A saved map says how its places were described: this session describes its own alike.
  std::optional<SavedMap> map;
  std::vector<Described> described;
  if (!a.map.empty()) {
    map.emplace();
    map->places = io::load_database(a.map, nullptr, &map->clouds);
    if (map->clouds.empty() && map->places.size() > 0) {
      throw io::InputError(a.map, 0,
                           "place clouds (this map was saved without them: build it "
                           "with `loopscan close`)");
    }
    described.push_back(described_map(a.map, map->places.config()));
  }
  const Configuration c = resolve_configuration(a.config, described);
  require_loop_closing(c, a.config);
  closure::LoopCloserConfig config = loop_closer_config(c);
  if (map) {
    const DatabaseConfig& saved = map->places.config();
    const DatabaseConfig& own = config.recognition.database;
    if (saved.fusion != own.fusion || saved.structure_weight != own.structure_weight) {
      throw io::InputError(a.map, 0,
                           "a map whose distances are fused as this configuration's (" +
                               fusion_name(own.fusion) + ", w_s " +
                               std::to_string(own.structure_weight) + "); it has " +
                               fusion_name(saved.fusion) + ", w_s " +
                               std::to_string(saved.structure_weight));
    }
    for (std::size_t i = 0; i < map->places.size(); ++i) {
      config.recognition.session =
          std::max(config.recognition.session, map->places.place(i).session + 1);
    }
  }
  const std::vector<KeyframePose> poses = io::read_sodso_poses(a.poses);
  // Streamed keyframe by keyframe, as a VO hands them over: memory follows the closer, not
  // the length of the recording.
  io::SodsoPointReader point_reader(a.points);
  std::optional<GroundTruth> gt;
  if (!a.gt.empty()) gt = read_ground_truth(a.gt, poses);
  const std::vector<int> resets = !a.reset_ids.empty()      ? io::read_incoming_ids(a.reset_ids)
                                  : c.mode == Mode::Default ? detect_vo_resets(poses, c.reset_jump_m)
                                                            : std::vector<int>{};
  std::optional<GroundTruth> map_gt;
  if (!a.map_gt.empty()) map_gt = read_ground_truth(a.map_gt, {});
  const ClosureRun run = run_closer(
      config, poses,
      [&point_reader, buffer = std::vector<IdPoint>()](int keyframe_id) mutable {
        point_reader.read_until(keyframe_id, buffer);
        return std::pair<const IdPoint*, std::size_t>(buffer.data(), buffer.size());
      },
      resets, !a.quiet, closure_queue(c), map ? &*map : nullptr);
  std::vector<IdPoint> after_last_keyframe;  // read to the end, so that a bad line is reported
  point_reader.read_until(std::numeric_limits<int>::max(), after_last_keyframe);
  const nlohmann::json m = write_closure_outputs(a.out, run, c, gt, map_gt).metrics;
  if (a.write_points) {
    io::write_sodso_points(
        a.out + "/pts_closed.txt",
        closure::reexpress_points(io::read_sodso_points(a.points), run.input, run.closed));
  }
  std::printf("%s: %zu keyframes, %d described; loops: %d proposed, %d accepted",
              method_name(c.method).c_str(), poses.size(), run.described,
              m["loops"]["proposed"].get<int>(), m["loops"]["accepted"].get<int>());
  if (gt) std::printf(" (%d false)", m["loops"]["false_accepted"].get<int>());
  if (map && run.anchored) std::printf("; in the map's frame from keyframe %d", run.anchored_at);
  if (map && !run.anchored) std::printf("; not localised in the map");
  if (gt) {
    std::printf("; ATE %.3f m -> %.3f m", m["ate_before_m"].get<double>(),
                m["ate_after_m"].get<double>());
  }
  std::printf("; %.2f ms per keyframe (add_keyframe p99 %.1f ms), %zu map places -> %s\n",
              m["ms_per_keyframe"]["total"].get<double>(),
              m["add_keyframe_latency_ms"]["p99"].get<double>(), run.map.size(),
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
  cmd->add_option("--reset-ids", a->reset_ids,
                  "file of keyframe ids where the VO reset (without it, default mode detects them)");
  cmd->add_option("--gt", a->gt, "ground truth (one line per frame id) for the metrics");
  cmd->add_option("--map", a->map,
                  "a saved map (another session's map.db): localise in it and extend it");
  cmd->add_option("--map-gt", a->map_gt,
                  "ground truth of the map's keyframes when it is not --gt's trajectory");
  cmd->add_option("--method", a->config.method,
                  "place recognition: sc | m2dp | delight | bev (default: the map's, else sc)");
  add_mode_option(*cmd, a->config);
  add_config_option(*cmd, a->config);
  cmd->add_flag("--write-points", a->write_points,
                "also write pts_closed.txt: the points re-expressed with the corrected poses");
  cmd->add_flag("--quiet", a->quiet, "no progress line");
  run_writing_dir(cmd, a, run_close);
}

}  // namespace loopscan::cli
