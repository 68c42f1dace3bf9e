#include "loopscan/io/kitti_sequence.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/limits.hpp"
#include "loopscan/io/line_reader.hpp"
#include "loopscan/io/parse_numbers.hpp"

namespace loopscan::io {
namespace {

std::string image_path(const std::string& dir, int camera, std::size_t i) {
  char name[32];
  std::snprintf(name, sizeof name, "/image_%d/%06zu.png", camera, i);
  return dir + name;
}

}  // namespace

KittiCalib read_kitti_calib(const std::string& path) {
  LineReader reader(path);
  std::string_view line;
  double p[2][12];
  bool seen[2] = {false, false};
  while (reader.next(line)) {
    Tokenizer tokens(line);
    std::string_view key;
    if (!tokens.next(key) || (key != "P0:" && key != "P1:")) continue;
    const int k = key == "P0:" ? 0 : 1;
    parse_exactly(reader, tokens, p[k], 12, "P0:/P1: followed by 12 numbers (3x4 projection)",
                  limits::kMaxCoordinateM);
    seen[k] = true;
  }
  for (int k = 0; k < 2; ++k) {
    if (!seen[k])
      throw InputError(path, 0, std::string("a line starting with P") + char('0' + k) + ":");
  }
  KittiCalib c{p[0][0], p[0][5], p[0][2], p[0][6], 0};
  if (!(c.fx >= 1 && c.fx <= 1e5) || !(c.fy >= 1 && c.fy <= 1e5)) {
    throw InputError(path, 0, "focal lengths in [1, 1e5] px in P0");
  }
  if (!(std::abs(c.cx) <= 1e5 && std::abs(c.cy) <= 1e5)) {
    throw InputError(path, 0, "a principal point within +-1e5 px in P0");
  }
  // Rectified pairs share the intrinsics; P1 differs from P0 only by -fx * baseline.
  if (!(std::abs(p[1][0] - c.fx) <= 1e-6 * c.fx)) {
    throw InputError(path, 0, "the focal length of P0 in P1 (a rectified pair)");
  }
  c.baseline_m = -p[1][3] / p[1][0];
  if (!(c.baseline_m > 0 && c.baseline_m <= 100)) {
    throw InputError(path, 0,
                     "P1's fourth value -fx * baseline with a baseline in (0, 100] m (right "
                     "camera)");
  }
  return c;
}

std::string KittiSequence::left(std::size_t i) const {
  return left_files.empty() ? image_path(dir, 0, i) : left_files.at(i);
}
std::string KittiSequence::right(std::size_t i) const {
  return right_files.empty() ? image_path(dir, 1, i) : right_files.at(i);
}

KittiSequence open_kitti_sequence(const std::string& dir) {
  KittiSequence s;
  s.dir = dir;
  s.calib = read_kitti_calib(dir + "/calib.txt");
  LineReader reader(dir + "/times.txt");
  std::string_view line;
  while (reader.next(line)) {
    if (is_blank(line)) continue;
    Tokenizer tokens(line);
    double t;
    parse_exactly(reader, tokens, &t, 1, "one timestamp in seconds", 1e300);
    if (!s.times.empty() && !(t > s.times.back())) {
      throw InputError(reader.path(), reader.line_number(), "timestamps in increasing order");
    }
    s.times.push_back(t);
  }
  for (std::size_t i = 0; i < s.frames(); ++i) {
    for (const std::string& image : {s.left(i), s.right(i)}) {
      if (!std::filesystem::exists(image)) {
        throw InputError(image, 0,
                         "an image for frame " + std::to_string(i) + " (times.txt has " +
                             std::to_string(s.frames()) + " frames)");
      }
    }
  }
  return s;
}

}  // namespace loopscan::io
