#pragma once
// 8-bit grayscale PNG files (the KITTI odometry images), with zlib: written with no row filter,
// read with all five filters. Other PNG kinds (colour, 16-bit, palette, interlaced) are
// rejected with an InputError naming what was found.
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
