#pragma once
// Reading one 8-bit gray image (PNG, JPEG, ...; colour is converted) for the image-side stages
// (VO, baselines). Header-only: the user links opencv_imgcodecs.
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "loopscan/io/errors.hpp"

namespace loopscan::vo {

inline cv::Mat read_gray_image(const std::string& path) {
  cv::Mat image = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (image.empty()) throw io::InputError(path, 0, "a readable image (PNG, JPEG, ...)");
  return image;
}

}  // namespace loopscan::vo
