#pragma once
// Shared by `close` and `slam`: a LoopCloser run over a keyframe sequence, its files
// (poses_closed.txt, trajectory_closed.txt, loops.csv, metrics.json, trajectory.svg) and the
// evaluation against ground truth when there is one.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "loopscan/closure/loop_closer.hpp"
#include "loopscan/config/configuration.hpp"

namespace loopscan::cli {

struct ClosureRun {
  std::vector<KeyframePose> input;   // the VO's poses (world-to-camera)
  std::vector<int> resets;           // sorted ids of the keyframes where the VO restarted
  std::vector<KeyframePose> closed;  // corrected, same ids and order
  std::vector<closure::Loop> loops;  // every verification
  closure::StageTimes times;
  double total_ms = 0;
  std::vector<double> add_keyframe_ms;  // each LoopCloser::add_keyframe call, in input order
  std::vector<int> described_ids;       // keyframes that were described, in input order
  int described = 0;
  int session = 0;
  bool anchored = true;  // in the saved map's frame (always true without one)
  int anchored_at = -1;
  Database map;  // every place (a saved map's and this session's, corrected)
  std::vector<PlaceCloud> clouds;
};

struct SavedMap {
  Database places;
  std::vector<PlaceCloud> clouds;
};

// Camera centres (world frame) of world-to-camera keyframe poses.
std::vector<Eigen::Vector3d> positions(const std::vector<KeyframePose>& poses);

// Streams the keyframes and their points (points sorted by keyframe id, as SO-DSO writes them)
// through a LoopCloser; `reset_ids`: keyframes where the VO restarted.
// `map` (optional): a saved map this session continues (config.recognition.session must be
// new to it).
ClosureRun run_closer(const closure::LoopCloserConfig& config,
                      const std::vector<KeyframePose>& poses, const std::vector<IdPoint>& points,
                      const std::vector<int>& reset_ids, bool progress, SavedMap* map = nullptr);

struct GroundTruth {
  std::string path;
  std::vector<Eigen::Vector3d> positions;          // per frame id
  std::vector<Eigen::Matrix<double, 3, 4>> poses;  // per frame id; empty for RobotCar
};

// Reads `path` (KITTI poses or RobotCar GPS, detected); throws io::InputError when a keyframe id
// has no line.
GroundTruth read_ground_truth(const std::string& path, const std::vector<KeyframePose>& poses);

struct ClosureFigures {
  std::string map;    // trajectories seen from above, loops as segments
  std::string error;  // APE over distance, before and after (empty without ground truth)
};

struct ClosureOutputs {
  nlohmann::json metrics;  // metrics.json's content
  ClosureFigures figures;  // also written as trajectory.svg and error.svg
};

// Writes every output into `dir` (map.db and config.yaml included) and returns them for a
// report. `map_gt`: ground truth of the saved map's keyframes (cross-session loops), else `gt`;
// a loop is true within c.closure.true_within_m.
ClosureOutputs write_closure_outputs(const std::string& dir, const ClosureRun& run,
                                     const Configuration& c, const std::optional<GroundTruth>& gt,
                                     const std::optional<GroundTruth>& map_gt);

// `run`'s loop-closing step: the closer of `c` over the VO's keyframes, files into `dir`.
ClosureOutputs close_vo_run(const std::string& dir, const std::vector<KeyframePose>& poses,
                            const std::vector<IdPoint>& points, const std::vector<int>& resets,
                            const std::optional<GroundTruth>& gt, const Configuration& c,
                            bool progress);

}  // namespace loopscan::cli
