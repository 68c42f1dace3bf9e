#pragma once
// Shared by `close` and `slam`: a LoopCloser run over a keyframe sequence, its files
// (poses_closed.txt, trajectory_closed.txt, loops.csv, metrics.json, trajectory.svg) and the
// evaluation against ground truth when there is one.
#include <functional>
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
  // Each add_keyframe call, in input order, without the time it waited for a queue slot (a
  // replay outruns the worker; a robot at its keyframe rate does not).
  std::vector<double> add_keyframe_ms;
  // The process's peak resident memory when closing ended (its input included; the
  // evaluation after it, with its own pose graph of every true revisit, not).
  double peak_memory_mb = 0;
  long queue_waits = 0;
  double queue_wait_ms = 0;
  bool background = false;
  std::vector<int> described_ids;       // keyframes that were described, in input order
  int described = 0;
  int session = 0;
  bool anchored = true;  // in the saved map's frame (always true without one)
  int anchored_at = -1;
  Database map;  // every place (a saved map's and this session's, corrected)
  std::vector<PlaceCloud> clouds;
  // Classifying, for the map, the places no verification needed (part of total_ms).
  double clouds_ms = 0;
};

struct SavedMap {
  Database places;
  std::vector<PlaceCloud> clouds;
};

// Camera centres (world frame) of world-to-camera keyframe poses.
std::vector<Eigen::Vector3d> positions(const std::vector<KeyframePose>& poses);

// Streams the keyframes and their points (points sorted by keyframe id, as SO-DSO writes them)
// through a loop closer; `reset_ids`: keyframes where the VO restarted. `background_queue`:
// 0 runs a LoopCloser on this thread; N > 0 a BackgroundLoopCloser with a queue of N, fed as
// fast as its worker takes the keyframes (closure_queue(c) gives the configured one).
// `map` (optional): a saved map this session continues (config.recognition.session must be
// new to it).
// Each keyframe's points as the VO handed them over: the points of the keyframe of this id (and
// of any earlier one not asked for), valid until the next call; asked in keyframe order.
using KeyframePoints = std::function<std::pair<const IdPoint*, std::size_t>(int keyframe_id)>;
KeyframePoints points_in_memory(const std::vector<IdPoint>& points);  // sorted by id
ClosureRun run_closer(const closure::LoopCloserConfig& config,
                      const std::vector<KeyframePose>& poses, const KeyframePoints& points,
                      const std::vector<int>& reset_ids, bool progress, int background_queue,
                      SavedMap* map = nullptr);
int closure_queue(const Configuration& c);

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
