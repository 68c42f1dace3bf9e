// loopscan slam: stereo images (KITTI layout) -> our VO -> place recognition -> verified loops
// -> pose graph: the VO's files, then the loop-closing ones (see `close`), in one output set.
#include <cstdio>

#include "closure_outputs.hpp"
#include "commands.hpp"
#include "options.hpp"
#include "output_sets.hpp"
#include "vo_outputs.hpp"

namespace loopscan::cli {
namespace {

struct SlamArgs {
  VoArgs vo;
  std::string method = "sc", mode = "default";
  int candidates = 3;
  double true_within_m = 10.0;
};

void run_slam(const SlamArgs& a) {
  const Method method = parse_method(a.method);  // before the VO runs
  closure::LoopCloserConfig config = closure::LoopCloserConfig::make(method, parse_mode(a.mode));
  config.candidates = a.candidates;
  std::printf("[1/2] stereo VO on %s\n", a.vo.kitti.c_str());
  const VoResult vo = run_vo_and_write(a.vo);
  std::optional<GroundTruth> gt;
  if (!vo.gt_path.empty()) gt = read_ground_truth(vo.gt_path, "kitti", vo.run.keyframe_poses);
  std::printf("[2/2] loop closing over %zu keyframes\n", vo.run.keyframe_poses.size());
  const ClosureRun run =
      run_closer(config, vo.run.keyframe_poses, vo.run.points, vo.run.reset_frames, !a.vo.quiet);
  const nlohmann::json m =
      write_closure_outputs(a.vo.out, run, config, gt, {}, a.true_within_m).metrics;
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
  cmd->add_option("--method", a->method, "place recognition: sc | m2dp | delight")
      ->capture_default_str();
  cmd->add_option("--mode", a->mode, "reference | default")->capture_default_str();
  cmd->add_option("--candidates", a->candidates, "places verified per keyframe")
      ->check(finite_in(1, 100))
      ->capture_default_str();
  cmd->add_option("--true-within", a->true_within_m,
                  "with ground truth: a loop is true when its keyframes are this close (m)")
      ->check(finite_in(0.01, 1000))
      ->capture_default_str();
  cmd->callback([cmd, a] {
    SlamArgs args = *a;
    refuse_inputs_inside(*cmd, args.vo.out);
    with_output_dir(args.vo.out, [&] { run_slam(args); });
  });
}

}  // namespace loopscan::cli
