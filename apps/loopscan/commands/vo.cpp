// loopscan vo: stereo images (KITTI odometry layout, or a raw EuRoC-layout camera) -> keyframe
// poses and DSO-like points in the SO-DSO history format (so `describe` runs on them unchanged),
// the trajectory and its accuracy.
#include "outputs/vo.hpp"
#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/output_sets.hpp"

namespace loopscan::cli {
namespace {

struct VoCommandArgs {
  VoArgs vo;
  ConfigFlags config;
};

}  // namespace

void add_vo_command(CLI::App& app) {
  auto a = std::make_shared<VoCommandArgs>();
  CLI::App* cmd = app.add_subcommand(
      "vo",
      "Stereo VO on a KITTI-layout sequence or a raw EuRoC-layout camera -> SO-DSO history "
      "files, trajectory (KITTI and TUM), metrics");
  add_vo_options(*cmd, a->vo, true);
  add_config_option(*cmd, a->config);
  cmd->callback([cmd, a] {
    VoCommandArgs args = *a;
    refuse_inputs_inside(*cmd, args.vo.out);
    const Configuration c = resolve_configuration(args.config);
    with_output_dir(args.vo.out, [&] { run_vo_and_write(args.vo, c); });
  });
}

}  // namespace loopscan::cli
