#pragma once
// ORB features for the Bag-of-Words baseline (OpenCV's detector and rBRIEF descriptor).
#include <opencv2/core.hpp>

namespace loopscan::baselines {

struct OrbConfig {
  int features = 4000;  // as in the paper
  float scale_factor = 1.2f;
  int levels = 8;
  int fast_threshold = 20;
};

// Nx32 CV_8U descriptors (N <= features) of an 8-bit gray (or BGR) image.
cv::Mat extract_orb(const cv::Mat& image, const OrbConfig& config = {});

}  // namespace loopscan::baselines
