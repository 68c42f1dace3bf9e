#pragma once
// GIST or BoW descriptors of the left images of given frames of a KITTI-layout sequence, with
// the time spent per image.
#include <vector>

#include <Eigen/Core>

#include "loopscan/baselines/gist.hpp"
#include "loopscan/baselines/orb_features.hpp"
#include "loopscan/baselines/vocabulary.hpp"
#include "loopscan/core/progress.hpp"
#include "loopscan/io/kitti_sequence.hpp"

namespace loopscan::baselines {

struct ImageDescriptors {
  std::vector<Eigen::VectorXf> gist;
  std::vector<BowVector> bow;
  double read_ms = 0;       // per image: decoding the PNG
  double extract_ms = 0;    // per image and thread: GIST, or ORB extraction
  double transform_ms = 0;  // per image: BoW vector from the ORB descriptors
  double mean_features = 0;
};

// Frames outside the sequence -> std::invalid_argument naming the frame. GIST runs on `threads`
// threads (identical descriptors). `progress`: (images described, all images).
ImageDescriptors describe_gist(const io::KittiSequence& sequence, const std::vector<int>& frames,
                               const GistConfig& config = {}, int threads = 1,
                               const ProgressFn& progress = {});
ImageDescriptors describe_bow(const io::KittiSequence& sequence, const std::vector<int>& frames,
                              const Vocabulary& vocabulary, const OrbConfig& config = {},
                              const ProgressFn& progress = {});

// ORB descriptors of every `step`-th left image (vocabulary training).
std::vector<cv::Mat> orb_of_sequence(const io::KittiSequence& sequence, int step,
                                     const OrbConfig& config = {});

}  // namespace loopscan::baselines
