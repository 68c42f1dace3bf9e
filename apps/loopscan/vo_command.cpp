// loopscan vo: stereo images (KITTI odometry layout) -> keyframe poses and DSO-like points in the
// SO-DSO history format (so `describe` runs on them unchanged), the trajectory and its accuracy.
#include "commands.hpp"
#include "output_sets.hpp"
#include "vo_outputs.hpp"

namespace loopscan::cli {

void add_vo_command(CLI::App& app) {
  auto a = std::make_shared<VoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "vo",
      "Stereo VO on a KITTI-layout sequence or a raw EuRoC-layout camera -> SO-DSO history "
      "files, trajectory (KITTI and TUM), metrics");
  add_vo_options(*cmd, *a, true);
  cmd->callback([cmd, a] {
    VoArgs args = *a;
    refuse_inputs_inside(*cmd, args.out);
    with_output_dir(args.out, [&] { run_vo_and_write(args); });
  });
}

}  // namespace loopscan::cli
