#include "loopscan/io/png.hpp"

#include <zlib.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>

#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/limits.hpp"

namespace loopscan::io {
namespace {

constexpr unsigned char kSignature[8] = {137, 'P', 'N', 'G', '\r', '\n', 26, '\n'};

void put_u32(std::string& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<char>((v >> s) & 0xff));
}

void put_chunk(std::string& out, const char type[4], const std::string& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  std::string body(type, 4);
  body += data;
  out += body;
  put_u32(out, static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(body.data()),
                                                static_cast<uInt>(body.size()))));
}

}  // namespace

void write_png_gray(const std::string& path, int width, int height,
                    const std::vector<std::uint8_t>& pixels) {
  std::string raw;
  raw.reserve(static_cast<std::size_t>(height) * (width + 1));
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);  // filter: none
    raw.append(reinterpret_cast<const char*>(&pixels[static_cast<std::size_t>(y) * width]), width);
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &size,
                reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()),
                6) != Z_OK) {
    throw std::runtime_error("cannot compress the image for " + path);
  }
  packed.resize(size);
  std::string out(reinterpret_cast<const char*>(kSignature), 8), ihdr;
  put_u32(ihdr, static_cast<std::uint32_t>(width));
  put_u32(ihdr, static_cast<std::uint32_t>(height));
  ihdr += std::string("\x08\x00\x00\x00\x00", 5);  // 8-bit gray, deflate, no filter, no interlace
  put_chunk(out, "IHDR", ihdr);
  put_chunk(out, "IDAT", packed);
  put_chunk(out, "IEND", "");
  write_file_atomic(path, out);
}

// PNG decoding to 8-bit gray: every non-interlaced PNG kind (gray, gray + alpha, RGB, RGBA,
// palette; 1 to 16 bits), converted to gray as OpenCV's IMREAD_GRAYSCALE does through libpng
// (rgb_to_gray with weights 0.299 / 0.587, 16-bit reduced to its high byte), sizes checked
// against io::limits before anything is allocated.
namespace {

inline std::uint32_t get_u32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) |
         std::uint32_t(p[3]);
}

inline int paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return (pa <= pb && pa <= pc) ? a : (pb <= pc ? b : c);
}

struct Header {
  int width = 0, height = 0, depth = 0, colour = 0, channels = 0;
  std::size_t row_bytes = 0;  // without the filter byte
  int pixel_bytes = 0;        // the filters' "bpp": at least 1
};

Header parse_header(const std::string& path, const unsigned char* d) {
  Header h;
  const std::uint32_t w = get_u32(d), hh = get_u32(d + 4);
  h.depth = d[8];
  h.colour = d[9];
  static const std::array<int, 7> kChannels = {1, 0, 3, 1, 2, 0, 4};
  h.channels = h.colour < 7 ? kChannels[h.colour] : 0;
  const bool depth_ok =
      h.channels != 0 &&
      (h.colour == 0
           ? (h.depth == 1 || h.depth == 2 || h.depth == 4 || h.depth == 8 || h.depth == 16)
       : h.colour == 3 ? (h.depth == 1 || h.depth == 2 || h.depth == 4 || h.depth == 8)
                       : (h.depth == 8 || h.depth == 16));
  if (!depth_ok || d[10] != 0 || d[11] != 0) {
    throw InputError(path, 0,
                     "a PNG header with a valid colour type and bit depth (found colour type " +
                         std::to_string(h.colour) + ", bit depth " + std::to_string(h.depth) + ")");
  }
  if (d[12] != 0) throw InputError(path, 0, "a non-interlaced PNG (found Adam7 interlacing)");
  if (w == 0 || hh == 0 || w > std::uint32_t(limits::kMaxImageSide) ||
      hh > std::uint32_t(limits::kMaxImageSide) ||
      std::int64_t(w) * std::int64_t(hh) > limits::kMaxImagePixels) {
    throw InputError(path, 0,
                     "an image of 1.." + std::to_string(limits::kMaxImageSide) +
                         " px a side and at most " + std::to_string(limits::kMaxImagePixels) +
                         " pixels (header says " + std::to_string(w) + "x" + std::to_string(hh) +
                         ")");
  }
  h.width = static_cast<int>(w);
  h.height = static_cast<int>(hh);
  h.row_bytes = (std::size_t(h.width) * h.channels * h.depth + 7) / 8;
  h.pixel_bytes = std::max(1, h.channels * h.depth / 8);
  return h;
}

// Undoes the row filters in place (PNG spec 9.2); `raw` rows are [filter byte | row bytes].
void unfilter(const std::string& path, const Header& h, unsigned char* raw) {
  const std::size_t stride = h.row_bytes + 1, bpp = static_cast<std::size_t>(h.pixel_bytes);
  for (int y = 0; y < h.height; ++y) {
    unsigned char* row = raw + std::size_t(y) * stride;
    const int filter = row[0];
    unsigned char* cur = row + 1;
    const unsigned char* up = y > 0 ? cur - stride : nullptr;
    if (filter > 4) {
      throw InputError(
          path, 0,
          "PNG row filter 0..4 (row " + std::to_string(y) + " has " + std::to_string(filter) + ")");
    }
    for (std::size_t x = 0; x < h.row_bytes; ++x) {
      const int a = x >= bpp ? cur[x - bpp] : 0, b = up ? up[x] : 0;
      const int c = (up && x >= bpp) ? up[x - bpp] : 0;
      const int predicted = filter == 1   ? a
                            : filter == 2 ? b
                            : filter == 3 ? (a + b) / 2
                            : filter == 4 ? paeth(a, b, c)
                                          : 0;
      cur[x] = static_cast<unsigned char>(cur[x] + predicted);
    }
  }
}

// Sample `i` of a row at the header's bit depth, scaled to 8 bits (16-bit: the high byte).
int sample8(const Header& h, const unsigned char* row, std::size_t i, bool palette_index) {
  if (h.depth == 16) return row[2 * i];
  if (h.depth == 8) return row[i];
  const int per_byte = 8 / h.depth, shift = 8 - h.depth * (1 + int(i % per_byte));
  const int v = (row[i / per_byte] >> shift) & ((1 << h.depth) - 1);
  return palette_index ? v : v * 255 / ((1 << h.depth) - 1);
}

// libpng's rgb_to_gray with OpenCV's weights (0.299, 0.587 as 29900, 58700 / 100000, scaled to
// 15 bits and truncated; blue takes the rest): 8-bit samples truncate, 16-bit ones round.
constexpr int kRed = 29900 * 32768 / 100000, kGreen = 58700 * 32768 / 100000;
constexpr int kBlue = 32768 - kRed - kGreen;

int to_gray(int r, int g, int b) { return (kRed * r + kGreen * g + kBlue * b) >> 15; }

int to_gray16(const unsigned char* rgb) {  // big-endian R, G, B; the high byte of the gray
  const auto s = [&](int c) { return (std::int64_t(rgb[2 * c]) << 8) | rgb[2 * c + 1]; };
  return static_cast<int>((kRed * s(0) + kGreen * s(1) + kBlue * s(2) + 16384) >> 15) >> 8;
}

}  // namespace

GrayPng read_png_gray(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, 0, "a readable PNG file");
  if (size > limits::kMaxImageFileBytes) {
    throw InputError(
        path, 0,
        "an image file of at most " + std::to_string(limits::kMaxImageFileBytes >> 20) + " MiB");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "a readable PNG file");
  const std::string bytes{std::istreambuf_iterator<char>(in), {}};
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 8 || std::memcmp(p, kSignature, 8) != 0) {
    throw InputError(path, 0, "a PNG file (signature missing)");
  }
  Header h;
  std::string idat, palette;
  bool header = false, end = false;
  for (std::size_t at = 8; at + 12 <= bytes.size() && !end;) {
    const std::uint32_t len = get_u32(p + at);
    if (len > bytes.size() - at - 12) throw InputError(path, 0, "a complete PNG chunk (truncated)");
    const std::string type(bytes.data() + at + 4, 4);
    const unsigned char* data = p + at + 8;
    if (crc32(crc32(0L, Z_NULL, 0), p + at + 4, len + 4) != get_u32(data + len)) {
      throw InputError(path, 0, "a valid CRC in PNG chunk " + type + " (corrupted)");
    }
    if (!header && type != "IHDR") throw InputError(path, 0, "the IHDR chunk first");
    if (type == "IHDR") {
      if (len != 13 || header) throw InputError(path, 0, "one 13-byte PNG header (IHDR)");
      h = parse_header(path, data);
      header = true;
    } else if (type == "PLTE") {
      if (len == 0 || len % 3 != 0 || len > 768)
        throw InputError(path, 0, "a PLTE chunk of 1..256 RGB entries");
      palette.assign(reinterpret_cast<const char*>(data), len);
    } else if (type == "IDAT") {
      idat.append(reinterpret_cast<const char*>(data), len);
    } else if (type == "IEND") {
      end = true;
    }
    at += 12 + len;
  }
  if (!header || !end) throw InputError(path, 0, "PNG chunks IHDR ... IEND (truncated)");
  if (h.colour == 3 && palette.empty()) throw InputError(path, 0, "a PLTE chunk (palette image)");

  const std::size_t stride = h.row_bytes + 1;
  std::string raw(stride * std::size_t(h.height), '\0');
  uLongf raw_size = static_cast<uLongf>(raw.size());
  if (uncompress(reinterpret_cast<Bytef*>(raw.data()), &raw_size,
                 reinterpret_cast<const Bytef*>(idat.data()),
                 static_cast<uLong>(idat.size())) != Z_OK ||
      raw_size != raw.size()) {
    throw InputError(path, 0, "image data of " + std::to_string(raw.size()) + " bytes (corrupted)");
  }
  auto* rows = reinterpret_cast<unsigned char*>(raw.data());
  unfilter(path, h, rows);

  GrayPng img;
  img.width = h.width;
  img.height = h.height;
  img.pixels.resize(std::size_t(h.width) * std::size_t(h.height));
  const auto* pal = reinterpret_cast<const unsigned char*>(palette.data());
  const std::size_t entries = palette.size() / 3;
  for (int y = 0; y < h.height; ++y) {
    const unsigned char* row = rows + std::size_t(y) * stride + 1;
    std::uint8_t* out = &img.pixels[std::size_t(y) * std::size_t(h.width)];
    if (h.colour == 0 && h.depth == 8) {  // the common case (KITTI, EuRoC): a plain copy
      std::memcpy(out, row, std::size_t(h.width));
      continue;
    }
    for (int x = 0; x < h.width; ++x) {
      const std::size_t s = std::size_t(x) * std::size_t(h.channels);
      int g = 0;
      if (h.colour == 0 || h.colour == 4) {  // gray (+ alpha, ignored)
        g = sample8(h, row, s, false);
      } else if (h.colour == 3) {
        const std::size_t k = static_cast<std::size_t>(sample8(h, row, s, true));
        if (k >= entries) throw InputError(path, 0, "palette indices within the PLTE chunk");
        g = to_gray(pal[3 * k], pal[3 * k + 1], pal[3 * k + 2]);
      } else if (h.depth == 16) {  // RGB (+ alpha, ignored)
        g = to_gray16(row + 2 * s);
      } else {
        g = to_gray(row[s], row[s + 1], row[s + 2]);
      }
      out[x] = static_cast<std::uint8_t>(g);
    }
  }
  return img;
}

}  // namespace loopscan::io
