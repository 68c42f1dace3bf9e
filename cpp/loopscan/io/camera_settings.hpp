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
// a finite number, focal lengths outside [1, 1e5] px, bf outside [1e-3, 1e7] px m, a principal
// point beyond +-1e5 px, sizes not whole or beyond io::limits (per side and in pixels).
StereoSettings read_orbslam_stereo(const std::string& path);

}  // namespace loopscan::io
