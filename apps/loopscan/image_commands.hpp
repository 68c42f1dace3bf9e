#pragma once
// The image baselines (GIST, BoW) behind `describe`, `evaluate` and `vocab`: the same
// directories, protocol and output files as the LiDAR-style methods.
#include <string>
#include <vector>

#include "loopscan/baselines/describe_images.hpp"

namespace loopscan::cli {

bool is_image_method(const std::string& method);  // "gist" | "bow"

// signatures.txt (GIST: a row of 512 a place) or bow.txt, and incoming_id_file.txt.
void write_image_descriptors(const std::string& dir, const std::string& method,
                             const baselines::ImageDescriptors& d, const std::vector<int>& ids);

struct ImageDescribeArgs {
  std::string method, kitti, keyframes, vocab, out;
  int features = 4000;
  int threads = 1;         // GIST
  bool reference = false;  // GIST: Lear's C GIST with the cover + crop (--mode reference)
};
// Describes the left image of every keyframe in <keyframes>/incoming_id_file.txt; writes
// signatures.txt (GIST, one row of 512 a place) or bow.txt (BoW), incoming_id_file.txt and
// timing.json.
void run_image_describe(const ImageDescribeArgs& a);

struct ImageEvaluateArgs {
  std::string method, signatures, gt, gt_format, against, gt2, out;
  double threshold_m = -1;
  int mask = -1;
};
void run_image_evaluate(const ImageEvaluateArgs& a);

}  // namespace loopscan::cli
