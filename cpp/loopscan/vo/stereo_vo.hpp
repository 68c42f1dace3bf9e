#pragma once
// Feature-based stereo visual odometry: corners tracked frame to frame (pyramidal Lucas-Kanade
// with a forward-backward check), pose by P3P RANSAC, then refined with each stereo-
// triangulated map point weighted by its uncertainty, keyframes by distance/rotation/track loss,
// windowed bundle adjustment (Ceres) over the latest keyframes. When tracking fails the VO resets
// explicitly: the map is rebuilt from the current stereo pair and the pose bridged with the
// constant-velocity model, so the trajectory stays in one world frame (the reset is reported).
//
// Per keyframe it exports DSO-like points (high-gradient pixels with stereo depth and gray value),
// expressed in the world frame with the keyframe's final pose when the keyframe leaves the window.
#include <future>
#include <memory>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "loopscan/core/types.hpp"
#include "loopscan/vo/image_points.hpp"
#include "loopscan/vo/vo_config.hpp"
#include "loopscan/vo/window_ba.hpp"

namespace loopscan::vo {

struct FrameResult {
  int frame = 0;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();  // online estimate
  bool keyframe = false;
  bool reset = false;  // tracking was lost before this frame: map rebuilt, pose bridged
  int tracked = 0;     // tracks surviving the forward-backward check
  int inliers = 0;     // tracks consistent with the pose
};

struct FinishedKeyframe {
  int frame = 0;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();  // final (after the window)
  bool reset = false;
  std::vector<CameraPoint> camera_points;  // exported points, left camera frame
};

// The keyframe's exported points in the world frame (id = frame), as SO-DSO writes them.
std::vector<IdPoint> world_points(const FinishedKeyframe& keyframe);

// Accumulated milliseconds. export_points and (with VoConfig::ba_on_worker) bundle_adjustment
// run on worker threads; ba_wait is the time the pose waited for an adjustment to finish.
struct StageTimes {
  double track = 0, pose = 0, keyframe = 0, bundle_adjustment = 0, export_points = 0;
  double ba_wait = 0;
};

class StereoVo {
 public:
  StereoVo(const StereoIntrinsics& camera, const VoConfig& config = {});

  // Rectified 8-bit left/right images of the next frame (frame ids increasing).
  FrameResult process(int frame, const cv::Mat& left, const cv::Mat& right);
  // Closes the window: every keyframe becomes finished; process() may not be called again.
  void finish();

  const std::vector<FinishedKeyframe>& finished_keyframes() const { return finished_; }
  // Every processed frame's pose, re-anchored on its keyframe's final pose.
  std::vector<Eigen::Isometry3d> trajectory() const;
  const std::vector<int>& reset_frames() const { return resets_; }
  const StageTimes& stage_times() const { return times_; }
  const StereoIntrinsics& camera() const { return camera_; }

 private:
  struct Observation {
    int point;
    double u, v, u_right;  // u_right NaN without a right match
  };
  struct Keyframe {
    int frame;
    Eigen::Isometry3d T_world_cam;
    bool reset;
    int index;  // among all keyframes
    std::vector<Observation> observations;
    // Selected on a worker thread from the keyframe's own copy of its images (a pure function
    // of them, so the result does not depend on timing); collected when the keyframe leaves.
    std::future<std::pair<std::vector<CameraPoint>, double>> camera_points;  // points, ms
  };
  struct Track {
    int point;
    cv::Point2f px;
  };
  struct FrameAnchor {
    int keyframe;  // index among all keyframes
    Eigen::Isometry3d T_kf_frame;
  };

  bool track(const Eigen::Isometry3d& predicted, const std::vector<cv::Mat>& pyramid,
             FrameResult& result);
  // P3P RANSAC against the tracks' map points (the minimal solver needs no prior), then the
  // inliers' uncertainty-weighted refinement.
  bool estimate_pose(Eigen::Isometry3d& T_world_cam, FrameResult& result);
  // The second frame's tracking and pose, without a motion model yet: from the forward motion
  // hypothesis whose pose keeps most tracks.
  bool track_from_standstill(const std::vector<cv::Mat>& pyramid, Eigen::Isometry3d& T_world_cam,
                             FrameResult& result);
  bool needs_keyframe(const Eigen::Isometry3d& T_world_cam, int inliers) const;
  void add_keyframe(int frame, const cv::Mat& left, const cv::Mat& right,
                    Eigen::Isometry3d& T_world_cam, bool reset);
  // The window's adjustment: started when a keyframe is added, applied (then the window
  // trimmed) after the next frame's tracking. Returns the newest keyframe's correction
  // (after * before^-1; identity when none was under way).
  void start_window_ba();
  Eigen::Isometry3d apply_window_ba();
  void finish_oldest();
  double right_u(const cv::Mat& left, const cv::Mat& right, float u, float v) const;

  StereoIntrinsics camera_;
  VoConfig config_;
  double px_scale_;
  std::vector<Eigen::Vector3d> map_;  // world points, index = point id
  std::vector<Eigen::Matrix3d> map_covariance_;  // their stereo triangulation's, world frame
  std::vector<Track> tracks_;
  std::vector<cv::Mat> previous_pyramid_;
  cv::Mat previous_left_;
  std::vector<Keyframe> window_;
  std::vector<FinishedKeyframe> finished_;
  std::vector<Eigen::Isometry3d> final_keyframe_poses_;  // by keyframe index (window: current)
  std::vector<FrameAnchor> anchors_;
  std::vector<int> resets_;
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d velocity_ = Eigen::Isometry3d::Identity();  // last_prev^-1 * last
  int keyframe_tracks_ = 0;  // tracks right after the last keyframe
  int keyframes_ = 0;
  bool started_ = false, closed_ = false;
  bool motion_known_ = false;  // a frame after the first has been posed
  StageTimes times_;
  struct WindowBa {
    std::unique_ptr<BaProblem> problem;  // on the heap: the worker holds it while StereoVo moves
    std::unordered_map<int, int> weight, local;  // per point id: depth weight, problem index
    int n_fixed = 0;
    std::future<double> done;  // the adjustment's milliseconds
  } ba_;
};

}  // namespace loopscan::vo
