#pragma once
// Imitates an omnidirectional LiDAR scan around each keyframe from the points a stereo VO
// exported so far (paper Sec. III-A): a local map of world points, cropped to the range.
#include <cstddef>
#include <deque>
#include <vector>

#include "loopscan/core/config.hpp"
#include "loopscan/core/scan/camera_points.hpp"

namespace loopscan {

// A keyframe's scan, ready to be described.
struct ReadyScan {
  KeyframePose keyframe;  // the keyframe the scan is centred on
  Cloud scan;             // filtered for the descriptor, camera frame of `keyframe`
  CameraPoints in_range;  // every map point within range, unfiltered (what verification aligns)
};

class ScanImitator {
 public:
  // Throws std::invalid_argument on an invalid config (see validate).
  explicit ScanImitator(const ImitationConfig& config = {});

  // Processes one keyframe and the points exported with it (world frame). Throws
  // std::invalid_argument when the pose has a NaN or infinite entry. Returns true when
  // the keyframe gets a scan; `in_range` then holds every local point within range, in the
  // camera frame, unfiltered. `reset` is the VO's reset signal (ignored in reference mode,
  // which detects resets itself as |t| < 1 m like the authors' code).
  bool add_keyframe(const KeyframePose& keyframe, const IdPoint* points, std::size_t n_points,
                    bool reset, Cloud& in_range);

  // The same step with the in-range points in single-precision SoA layout, for
  // filter_camera_points (the default-mode fast path).
  bool add_keyframe(const KeyframePose& keyframe, const IdPoint* points, std::size_t n_points,
                    bool reset, CameraPoints& in_range);

  // add_keyframe plus the descriptor's filter, through the mode's path (reference: double and
  // the authors' filters; default: the single-precision vectorised path): the filtered scan
  // the keyframe gets, or false. `in_range_count` (optional): points before filtering.
  bool next_scan(const KeyframePose& keyframe, const IdPoint* points, std::size_t n_points,
                 bool reset, ScanFilter filter, Cloud& scan, std::size_t* in_range_count = nullptr);

  // The streaming step every pipeline uses: feeds a keyframe and appends the scans that are
  // ready now. Forward-only (lookahead_m = 0, or reference mode): this keyframe's scan, when it
  // gets one. Two-sided: the scans of the earlier keyframes the VO is now lookahead_m past (all
  // waiting ones at a reset, which ends their map). Throws like add_keyframe.
  void push(const KeyframePose& keyframe, const IdPoint* points, std::size_t n_points, bool reset,
            ScanFilter filter, std::vector<ReadyScan>& ready);
  // End of the sequence: the scans of the keyframes still waiting, from what the map holds.
  void finish(ScanFilter filter, std::vector<ReadyScan>& ready);
  bool two_sided() const { return config_.mode == Mode::Default && config_.lookahead_m > 0; }
  // Keyframes waiting for their two-sided scan.
  std::size_t waiting() const { return pending_.size(); }

  // The unfiltered in-range points of the last keyframe next_scan gave a scan (camera frame,
  // single precision): what loop verification aligns.
  void last_in_range(std::vector<Eigen::Vector3f>& out) const;

  // Points left out because a coordinate or the gray value was NaN, infinite or beyond
  // single precision.
  std::size_t unusable_points() const { return unusable_points_; }

  // Forgets the local map; the next `init_frames` keyframes get no scan.
  void reset();

  std::size_t local_map_size() const {
    return config_.mode == Mode::Reference ? local_.size() : world_.size();
  }
  const ImitationConfig& config() const { return config_; }

 private:
  // Steps 1-3 of add_keyframe; true when the keyframe gets a scan.
  bool accumulate(const KeyframePose& keyframe, const IdPoint* points, std::size_t n_points,
                  bool reset);

  void check_pose(const KeyframePose& keyframe) const;
  void append_points(const IdPoint* points, std::size_t n_points);

  ImitationConfig config_;
  // Step 4, crop: out-of-range points leave the map for good. Reference mode in double with
  // the authors' arithmetic; default mode in float SoA.
  void crop_reference(const KeyframePose& keyframe, Cloud& in_range);
  // forget_out_of_range = false: the two-sided crop around a waiting keyframe, which leaves the
  // map as it is (prune_two_sided decides what leaves it).
  void crop_fast(const KeyframePose& keyframe, CameraPoints& in_range,
                 bool forget_out_of_range = true);

  struct Pending {
    KeyframePose keyframe;
    double path_m;  // distance travelled when it arrived
  };
  // Two-sided scans: crop around a waiting keyframe without dropping map points.
  void emit_two_sided(const Pending& p, ScanFilter filter, std::vector<ReadyScan>& ready);
  // Drops map points out of range of both the newest and the oldest waiting keyframe.
  void prune_two_sided(const KeyframePose& newest);
  std::deque<Pending> pending_;
  double path_m_ = 0;
  Eigen::Vector3d last_centre_ = Eigen::Vector3d::Zero();
  bool has_centre_ = false;

  std::vector<PointI> local_;   // reference mode: world frame, double (the authors' arithmetic)
  CameraPoints world_;          // default mode: world frame, float SoA (4x less memory traffic)
  Cloud in_range_;              // next_scan's scratch, reference mode
  CameraPoints in_range_fast_;  // next_scan's scratch, default mode
  int frames_since_reset_ = 0;
  std::size_t unusable_points_ = 0;
};

// Applies the configured de-duplicating filter to an in-range cloud.
Cloud filter_scan(const Cloud& in_range, ScanFilter filter, const ImitationConfig& config);

}  // namespace loopscan
