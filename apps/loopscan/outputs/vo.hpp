#pragma once
// Shared by `vo` and `run`: the VO over a KITTI-layout sequence with a progress bar, its files
// (SO-DSO history, KITTI trajectory, vo.json) and KITTI-style accuracy against ground truth.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "loopscan/config/configuration.hpp"
#include "loopscan/eval/odometry_metrics.hpp"
#include "loopscan/vo/run_sequence.hpp"

namespace loopscan::cli {

struct VoArgs {
  std::string kitti, out, gt;  // gt: default <kitti>/poses.txt when it exists
  std::string euroc;           // raw stereo in the EuRoC layout instead (gt: a TUM file)
  int first = 0, frames = -1;
  std::vector<int> blank_frames;
  bool quiet = false;
};

struct VoResult {
  vo::SequenceRun run;
  std::string gt_path;                                // empty: no ground truth
  std::vector<Eigen::Matrix<double, 3, 4>> gt_poses;  // every line of gt_path (camera-to-world)
  nlohmann::json summary;
};

// `allow_euroc`: --euroc as an alternative to --kitti (the `vo` command).
void add_vo_options(CLI::App& cmd, VoArgs& a, bool allow_euroc = false);

// Runs the VO of `c` (c.vo; accuracy by c.odometry_metrics), writes poses_history_file.txt,
// pts_history_file.txt, trajectory.txt (KITTI, every frame), trajectory_tum.txt (TUM; the body
// frame for EuRoC) and vo.json into a.out, prints the summary (fps, ms per stage, metrics).
VoResult run_vo_and_write(const VoArgs& a, const Configuration& c);

}  // namespace loopscan::cli
