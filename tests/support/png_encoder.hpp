#pragma once
// An independent PNG encoder for the decoder's tests: any colour type and bit depth, one row
// filter for every row, optional palette and interlace flag, chunks built by hand.
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace loopscan::test {

struct PngSpec {
  int width = 1, height = 1, colour = 0, depth = 8, filter = 0, interlace = 0;
  std::vector<std::uint8_t> rows;  // unfiltered row bytes, height * row_bytes()
  std::string palette;             // PLTE payload (colour 3)
  int channels() const { return colour == 2 ? 3 : colour == 4 ? 2 : colour == 6 ? 4 : 1; }
  int row_bytes() const { return (width * channels() * depth + 7) / 8; }
  int pixel_bytes() const { return std::max(1, channels() * depth / 8); }
};

inline void png_u32(std::string& s, std::uint32_t v) {
  for (int k = 24; k >= 0; k -= 8) s.push_back(static_cast<char>((v >> k) & 0xff));
}

inline void png_chunk(std::string& out, const std::string& type, const std::string& data) {
  png_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = type + data;
  out += body;
  png_u32(out, static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(body.data()),
                                                static_cast<uInt>(body.size()))));
}

// `rows` must hold height * row_bytes() bytes; filters above 4 are written as given (with no
// prediction), for the decoder's error path.
inline std::string encode_png(const PngSpec& s) {
  const int rb = s.row_bytes(), bpp = s.pixel_bytes();
  std::string raw;
  for (int y = 0; y < s.height; ++y) {
    raw.push_back(static_cast<char>(s.filter));
    const std::uint8_t* row = &s.rows[static_cast<std::size_t>(y) * rb];
    const std::uint8_t* up = y ? row - rb : nullptr;
    for (int x = 0; x < rb; ++x) {
      const int a = x >= bpp ? row[x - bpp] : 0, b = up ? up[x] : 0;
      const int c = (up && x >= bpp) ? up[x - bpp] : 0;
      const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
      const int pred[5] = {0, a, b, (a + b) / 2, (pa <= pb && pa <= pc) ? a : (pb <= pc ? b : c)};
      raw.push_back(static_cast<char>((row[x] - (s.filter < 5 ? pred[s.filter] : 0)) & 0xff));
    }
  }
  uLongf n = compressBound(raw.size());
  std::string z(n, '\0');
  compress(reinterpret_cast<Bytef*>(z.data()), &n, reinterpret_cast<const Bytef*>(raw.data()),
           raw.size());
  z.resize(n);
  std::string out("\x89PNG\r\n\x1a\n", 8), ihdr;
  png_u32(ihdr, static_cast<std::uint32_t>(s.width));
  png_u32(ihdr, static_cast<std::uint32_t>(s.height));
  ihdr += std::string{static_cast<char>(s.depth), static_cast<char>(s.colour), 0, 0,
                      static_cast<char>(s.interlace)};
  png_chunk(out, "IHDR", ihdr);
  if (!s.palette.empty()) png_chunk(out, "PLTE", s.palette);
  png_chunk(out, "IDAT", z);
  png_chunk(out, "IEND", "");
  return out;
}

// A valid 1x1 file whose header announces width x height instead (for the size limits).
inline std::string png_announcing(std::uint32_t width, std::uint32_t height) {
  PngSpec one;
  one.rows = {0};
  std::string bytes = encode_png(one);
  std::string ihdr;
  png_u32(ihdr, width);
  png_u32(ihdr, height);
  ihdr += std::string{8, 0, 0, 0, 0};
  std::string patched;
  png_chunk(patched, "IHDR", ihdr);
  return bytes.replace(8, patched.size(), patched);
}

}  // namespace loopscan::test
