#pragma once
// Sparse stereo matching on rectified 8-bit images: sum of absolute differences over a square
// window along the row, a uniqueness test and equiangular sub-pixel refinement.
#include <opencv2/core.hpp>

namespace loopscan::vo {

struct StereoSearch {
  double min_disparity = 0, max_disparity = 0;  // px
  int half_window = 2;
  double uniqueness = 0.85;
  bool left_right_check = false;  // match back from the right image, agree within 1 px
};

// Disparity (x_left - x_right, sub-pixel) of the left pixel (x, y), or NaN when the window leaves
// either image, the minimum lies on the search border, or it is not unique.
double match_disparity(const cv::Mat& left, const cv::Mat& right, int x, int y,
                       const StereoSearch& search);

}  // namespace loopscan::vo
