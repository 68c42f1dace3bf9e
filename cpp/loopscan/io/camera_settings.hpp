#pragma once
// Stereo camera settings in ORB-SLAM2's YAML layout (`Camera.fx: 707.0912` lines), the
// `--calib` of simulate and render.
#include <string>

namespace loopscan::io {

// A rectified stereo pair: intrinsics, image size, focal length times baseline.
struct StereoSettings {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;
  double bf = 0;  // px * m
};

// Reads Camera.fx, fy, cx, cy, width, height, bf from top-level `key: value` lines ('%' and
// '#' start comments; indented lines and other keys are ignored). Errors are InputErrors
// naming the file, the line and what was expected: a missing file or key, a value that is not
// a finite number, a focal length, bf or size outside (0, 1e6] (sizes: whole pixels up to
// io::limits::kMaxImageSide), a principal point beyond +-1e6 px.
StereoSettings read_orbslam_stereo(const std::string& path);

}  // namespace loopscan::io
