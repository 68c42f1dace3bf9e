#pragma once
// Valid inputs of every format, made in-process (the seeds the fuzzer mutates).
#include <string>

#include "loopscan/io/vocabulary_file.hpp"

namespace loopscan::fuzz {

// SO-DSO poses (`id` + 3x4, ids 0, 2, 4, ...) or KITTI poses (3x4 a line) of a gentle drive.
std::string poses_text(bool with_ids, int n);
// SO-DSO points: `per_keyframe` points for each of the keyframes 0, 2, 4, ...
std::string points_text(int keyframes, int per_keyframe);
std::string gzip(const std::string& text);
std::string matrix_text(int rows, int cols);
extern const std::string kCalib;  // a KITTI calib.txt (P0..P3, Tr)
io::VocabularyData small_vocabulary(int branching);  // depth 2
std::string vocabulary_text();    // ORBvoc.txt of a k 3, L 2 tree
std::string camera_yaml();        // ORB-SLAM2 settings of the KITTI 04-12 camera
// A gray image of `width` x `height` random texture, encoded as ".png" or ".jpg" (OpenCV).
std::string image_bytes(const char* ext, int type, int width = 13, int height = 9);

}  // namespace loopscan::fuzz
