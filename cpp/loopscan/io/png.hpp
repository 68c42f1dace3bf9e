#pragma once
// PNG files with zlib: 8-bit grayscale written with no row filter (the KITTI odometry
// layout); any non-interlaced PNG read as 8-bit gray (all five row filters; colour, palette
// and 16-bit converted as libpng's rgb_to_gray / strip_16 do). Interlaced files, sizes beyond
// io::limits and damaged chunks are rejected with an InputError naming the file and the cause.
#include <cstdint>
#include <string>
#include <vector>

namespace loopscan::io {

struct GrayPng {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // row-major
};

// Atomic (temp file + rename).
void write_png_gray(const std::string& path, int width, int height,
                    const std::vector<std::uint8_t>& pixels);
GrayPng read_png_gray(const std::string& path);

}  // namespace loopscan::io
