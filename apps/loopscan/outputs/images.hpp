#pragma once
// The image baselines (GIST, BoW) behind `describe`, `evaluate` and `vocab`: the same
// directories, protocol and output files as the LiDAR-style methods.
#include <string>
#include <vector>

#include "loopscan/baselines/describe_images.hpp"
#include "loopscan/config/configuration.hpp"

namespace loopscan::cli {

bool is_image_method(const std::string& method);  // "gist" | "bow"

// signatures.txt (GIST: a row of 512 a place) or bow.txt, incoming_id_file.txt and config.yaml
// (`c`, whose method says which).
void write_image_descriptors(const std::string& dir, const baselines::ImageDescriptors& d,
                             const std::vector<int>& ids, const Configuration& c);

struct ImageDescribeArgs {
  std::string kitti, keyframes, vocab, out;
  int threads = 1;  // GIST
};
// Describes the left image of every keyframe in <keyframes>/incoming_id_file.txt with the image
// baseline of `c` (reference mode: Lear's C GIST); writes what write_image_descriptors does and
// timing.json.
void run_image_describe(const ImageDescribeArgs& a, const Configuration& c);

struct ImageEvaluateArgs {
  std::string signatures, gt, against, gt2, out;
};
// The same-session protocol of `c`, or the cross-session one with --against; reference mode
// counts loops as the paper's Matlab code did.
void run_image_evaluate(const ImageEvaluateArgs& a, const Configuration& c);

}  // namespace loopscan::cli
