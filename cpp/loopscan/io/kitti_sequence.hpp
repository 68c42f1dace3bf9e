#pragma once
// A KITTI odometry sequence on disk (the real dataset or `loopscan render` output):
// image_0/NNNNNN.png (left), image_1/ (right), calib.txt (P0..P3), times.txt.
#include <cstddef>
#include <string>
#include <vector>

namespace loopscan::io {

// Rectified stereo intrinsics from calib.txt: fx, fy, cx, cy of P0 and the baseline
// -P1[0][3] / fx (metres).
struct KittiCalib {
  double fx = 0, fy = 0, cx = 0, cy = 0, baseline_m = 0;
};

// Needs lines "P0:" and "P1:" with 12 numbers each (other lines, e.g. P2, P3, Tr, are read
// past). Errors name the file and line.
KittiCalib read_kitti_calib(const std::string& path);

struct KittiSequence {
  std::string dir;
  KittiCalib calib;
  std::vector<double> times;  // seconds, one per frame
  // Explicit image paths (other layouts, e.g. EuRoC's timestamp names); empty: KITTI's names.
  std::vector<std::string> left_files, right_files;
  std::size_t frames() const { return times.size(); }
  std::string left(std::size_t i) const;   // image_0/NNNNNN.png
  std::string right(std::size_t i) const;  // image_1/NNNNNN.png
};

// Checks calib.txt, times.txt (one increasing number a line) and that every frame has both
// images; the first missing one is named in the error.
KittiSequence open_kitti_sequence(const std::string& dir);

}  // namespace loopscan::io
