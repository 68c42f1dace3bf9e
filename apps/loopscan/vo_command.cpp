// loopscan vo: stereo images (KITTI odometry layout) -> keyframe poses and DSO-like points in the
// SO-DSO history format (so `describe` runs on them unchanged), the trajectory and its accuracy.
#include "commands.hpp"
#include "vo_outputs.hpp"

namespace loopscan::cli {

void add_vo_command(CLI::App& app) {
  auto a = std::make_shared<VoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "vo", "Stereo VO on a KITTI-layout sequence -> SO-DSO history files, trajectory, metrics");
  add_vo_options(*cmd, *a);
  cmd->callback([a] { run_vo_and_write(*a); });
}

}  // namespace loopscan::cli
