#pragma once
// Runs the stereo VO over a KITTI odometry sequence on disk (the next frame's images are read
// on a second thread while the current one is processed).
#include <functional>
#include <vector>

#include <Eigen/Geometry>

#include "loopscan/core/types.hpp"
#include "loopscan/io/kitti_sequence.hpp"
#include "loopscan/vo/stereo_vo.hpp"

namespace loopscan::vo {

struct SequenceRunOptions {
  int first = 0;
  int frames = -1;  // all
  // Frames whose images are replaced by black ones (tests the explicit reset).
  std::vector<int> blank_frames;
  std::function<void(int done, int total, double fps)> progress;
  // Applied to each raw pair on the reader thread before the VO sees it (rectification of raw
  // cameras, see euroc.hpp); the pair's size must stay that of the calibration.
  std::function<void(cv::Mat& left, cv::Mat& right)> prepare_pair;
};

struct SequenceRun {
  StereoIntrinsics camera;
  std::vector<int> frame_ids;                 // sequence frame of each trajectory entry
  std::vector<Eigen::Isometry3d> trajectory;  // camera-to-world, every frame (refined)
  std::vector<KeyframePose> keyframe_poses;   // SO-DSO: world-to-camera, id = frame
  std::vector<IdPoint> points;                // SO-DSO: world frame, id = keyframe's frame
  std::vector<FinishedKeyframe> keyframes;
  std::vector<int> reset_frames;
  StageTimes stage_ms;  // per frame
  double load_ms = 0;   // per frame, reading the two PNGs (on the reader thread)
  double seconds = 0, fps = 0;
  double mean_points_per_keyframe = 0;
};

// Intrinsics from calib.txt and the first image's size.
StereoIntrinsics intrinsics_of(const io::KittiSequence& sequence);

SequenceRun run_stereo_vo(const io::KittiSequence& sequence, const VoConfig& config = {},
                          const SequenceRunOptions& options = {});

}  // namespace loopscan::vo
