// loopscan slam: stereo images (KITTI layout) -> our VO -> place recognition -> verified loops
// -> pose graph: the VO's files, then the loop-closing ones (see `close`), in one output set.
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "outputs/closure.hpp"
#include "outputs/vo.hpp"

namespace loopscan::cli {
namespace {

struct SlamArgs {
  VoArgs vo;
  ConfigFlags config;
};

void run_slam(const SlamArgs& a, const Configuration& c) {
  const closure::LoopCloserConfig config = loop_closer_config(c);
  std::printf("[1/2] stereo VO on %s\n", a.vo.kitti.c_str());
  const VoResult vo = run_vo_and_write(a.vo, c);
  std::optional<GroundTruth> gt;
  if (!vo.gt_path.empty()) gt = read_ground_truth(vo.gt_path, vo.run.keyframe_poses);
  std::printf("[2/2] loop closing over %zu keyframes\n", vo.run.keyframe_poses.size());
  const ClosureRun run = run_closer(config, vo.run.keyframe_poses, points_in_memory(vo.run.points),
                                    vo.run.reset_frames, !a.vo.quiet, closure_queue(c));
  const nlohmann::json m = write_closure_outputs(a.vo.out, run, c, gt, {}).metrics;
  std::printf("loops: %d accepted", m["loops"]["accepted"].get<int>());
  if (gt) {
    std::printf(" (%d false); keyframe ATE %.3f m -> %.3f m",
                m["loops"]["false_accepted"].get<int>(), m["ate_before_m"].get<double>(),
                m["ate_after_m"].get<double>());
  }
  std::printf("; loop closing %.2f ms per keyframe -> %s\n",
              m["ms_per_keyframe"]["total"].get<double>(), shown(a.vo.out).c_str());
}

}  // namespace

void add_slam_command(CLI::App& app) {
  auto a = std::make_shared<SlamArgs>();
  CLI::App* cmd = app.add_subcommand(
      "slam", "Stereo VO, place recognition and loop closing on a KITTI-layout sequence");
  add_vo_options(*cmd, a->vo);
  cmd->add_option("--method", a->config.method, "place recognition: sc | m2dp | delight | bev");
  add_mode_option(*cmd, a->config);
  add_config_option(*cmd, a->config);
  cmd->callback([cmd, a] {
    SlamArgs args = *a;
    refuse_inputs_inside(*cmd, args.vo.out);
    const Configuration c = resolve_configuration(args.config);  // before the VO runs
    require_loop_closing(c, args.config);
    with_output_dir(args.vo.out, [&] { run_slam(args, c); });
  });
}

}  // namespace loopscan::cli
