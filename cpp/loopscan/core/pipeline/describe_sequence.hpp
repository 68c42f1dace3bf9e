#pragma once
// A whole VO sequence to place signatures, walking keyframes in id order exactly like the
// authors' offline tool: points with id <= the keyframe's id join the local map, a scan is
// imitated and filtered, then described.
#include <vector>

#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/progress.hpp"
#include "loopscan/core/scan/scan_imitator.hpp"

namespace loopscan {

struct SequenceOptions {
  Method method = Method::ScanContext;
  ImitationConfig imitation;
  DescriptorConfig descriptors;
  std::vector<int> reset_ids;  // keyframes where the VO restarted (default mode only)
  int threads = 1;  // imitation is sequential; descriptions of a batch of scans run in parallel
  static constexpr int kMaxThreads = 1024;
  ProgressFn progress;  // (keyframes walked, all keyframes); results do not depend on it
  // Consistent options for a mode and range (the paper: 45 m).
  static SequenceOptions make(Method method, Mode mode, double range_m = 45.0);
};

struct SequenceSignatures {
  std::vector<int> keyframe_ids;  // one per signature
  std::vector<Signature> signatures;
  std::vector<Eigen::Matrix3d> frames;  // descriptor axes in the camera frame (see describe)
  double imitate_ms = 0;                // mean per described keyframe: crop + filter
  double describe_ms = 0;               // mean per described keyframe (CPU time of one thread)
  double mean_in_range = 0, mean_filtered = 0;  // points per scan
};

// Throws std::invalid_argument on keyframe ids not increasing, point ids not sorted, invalid
// options (threads outside [1, kMaxThreads], configs that fail validate) and on a non-finite
// keyframe pose.
SequenceSignatures describe_sequence(const std::vector<KeyframePose>& poses,
                                     const std::vector<IdPoint>& points,
                                     const SequenceOptions& options);

// Default-mode reset detection when the VO gives no signal: a keyframe that lands within 1 m
// of the VO origin (where a restarted VO puts its first keyframe) after a jump of more than
// `jump_m` from the previous keyframe. Unlike the reference heuristic it does not fire when
// the camera merely drives past its starting point again.
std::vector<int> detect_vo_resets(const std::vector<KeyframePose>& poses, double jump_m = 5.0);

}  // namespace loopscan
