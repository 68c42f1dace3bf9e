#include "loopscan/baselines/orb_features.hpp"

#include <stdexcept>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace loopscan::baselines {

cv::Mat extract_orb(const cv::Mat& image, const OrbConfig& c) {
  if (image.empty()) throw std::invalid_argument("ORB: empty image");
  cv::Mat gray = image;
  if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  thread_local cv::Ptr<cv::ORB> orb;
  thread_local OrbConfig made{-1, 0, 0, 0};
  if (!orb || made.features != c.features || made.scale_factor != c.scale_factor ||
      made.levels != c.levels || made.fast_threshold != c.fast_threshold) {
    orb = cv::ORB::create(c.features, c.scale_factor, c.levels, 31, 0, 2, cv::ORB::HARRIS_SCORE,
                          31, c.fast_threshold);
    made = c;
  }
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  orb->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
  if (descriptors.empty()) return cv::Mat(0, 32, CV_8U);
  return descriptors;
}

}  // namespace loopscan::baselines
