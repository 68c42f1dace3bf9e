#pragma once
// Reading one 8-bit gray image for the image-side stages (VO, baselines): PNG through
// loopscan's own decoder (io::read_png_gray: colour converted, sizes bounded, errors name the
// file), JPEG through OpenCV after a size check of its frame header; other formats are refused
// (their size could not be checked before decoding).
#include <string>

#include <opencv2/core.hpp>

namespace loopscan::vo {

// Throws io::InputError naming the file when it is missing, unreadable, damaged or larger
// than io::limits allows.
cv::Mat read_gray_image(const std::string& path);

}  // namespace loopscan::vo
