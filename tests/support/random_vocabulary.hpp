#pragma once
// Random ORB-like descriptors and a vocabulary trained on them, for the BoW tests.
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "loopscan/baselines/vocabulary.hpp"

namespace loopscan::test {

inline cv::Mat random_descriptors(int n, std::mt19937& rng) {
  cv::Mat m(n, 32, CV_8U);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < 32; ++c) m.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(rng() & 0xff);
  return m;
}

inline baselines::Vocabulary random_vocabulary(unsigned seed, int n_images, int per_image, int k,
                                               int L, std::vector<cv::Mat>* training = nullptr) {
  std::mt19937 rng(seed);
  std::vector<cv::Mat> images;
  for (int i = 0; i < n_images; ++i) images.push_back(random_descriptors(per_image, rng));
  baselines::VocabularyConfig config;
  config.branching = k;
  config.depth = L;
  if (training) *training = images;
  return baselines::train_vocabulary(images, config);
}

}  // namespace loopscan::test
