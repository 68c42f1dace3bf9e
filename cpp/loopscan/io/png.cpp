#include "loopscan/io/png.hpp"

#include <zlib.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/errors.hpp"

namespace loopscan::io {
namespace {

constexpr unsigned char kSignature[8] = {137, 'P', 'N', 'G', '\r', '\n', 26, '\n'};

void put_u32(std::string& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<char>((v >> s) & 0xff));
}

std::uint32_t get_u32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) |
         std::uint32_t(p[3]);
}

void put_chunk(std::string& out, const char type[4], const std::string& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  std::string body(type, 4);
  body += data;
  out += body;
  put_u32(out, static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(body.data()),
                                                static_cast<uInt>(body.size()))));
}

int paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return (pa <= pb && pa <= pc) ? a : (pb <= pc ? b : c);
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

GrayPng read_png_gray(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open the PNG file");
  const std::string bytes{std::istreambuf_iterator<char>(in), {}};
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 8 || std::memcmp(p, kSignature, 8) != 0) {
    throw InputError(path, 0, "a PNG file (signature missing)");
  }
  GrayPng img;
  std::string idat;
  bool header = false, end = false;
  for (std::size_t at = 8; at + 12 <= bytes.size() && !end;) {
    const std::uint32_t len = get_u32(p + at);
    if (len > bytes.size() - at - 12) throw InputError(path, 0, "a complete PNG chunk (truncated)");
    const std::string type(bytes.data() + at + 4, 4);
    const unsigned char* data = p + at + 8;
    if (crc32(crc32(0L, Z_NULL, 0), p + at + 4, len + 4) != get_u32(data + len)) {
      throw InputError(path, 0, "a valid CRC in PNG chunk " + type + " (corrupted)");
    }
    if (type == "IHDR") {
      if (len != 13) throw InputError(path, 0, "a 13-byte PNG header");
      img.width = static_cast<int>(get_u32(data));
      img.height = static_cast<int>(get_u32(data + 4));
      if (data[8] != 8 || data[9] != 0 || data[12] != 0 || img.width <= 0 || img.height <= 0 ||
          img.width > (1 << 15) || img.height > (1 << 15)) {
        throw InputError(path, 0,
                         "an 8-bit grayscale, non-interlaced PNG (found bit depth " +
                             std::to_string(data[8]) + ", colour type " + std::to_string(data[9]) +
                             ", interlace " + std::to_string(data[12]) + ")");
      }
      header = true;
    } else if (type == "IDAT") {
      idat.append(reinterpret_cast<const char*>(data), len);
    } else if (type == "IEND") {
      end = true;
    }
    at += 12 + len;
  }
  if (!header || !end) throw InputError(path, 0, "PNG chunks IHDR ... IEND (truncated)");
  const std::size_t stride = static_cast<std::size_t>(img.width) + 1;
  std::string raw(stride * img.height, '\0');
  uLongf raw_size = static_cast<uLongf>(raw.size());
  if (uncompress(reinterpret_cast<Bytef*>(raw.data()), &raw_size,
                 reinterpret_cast<const Bytef*>(idat.data()),
                 static_cast<uLong>(idat.size())) != Z_OK ||
      raw_size != raw.size()) {
    throw InputError(path, 0, "image data of " + std::to_string(raw.size()) + " bytes (corrupted)");
  }
  img.pixels.assign(static_cast<std::size_t>(img.width) * img.height, 0);
  for (int y = 0; y < img.height; ++y) {
    const auto* row = reinterpret_cast<const unsigned char*>(raw.data()) + y * stride;
    const int filter = row[0];
    std::uint8_t* out = &img.pixels[static_cast<std::size_t>(y) * img.width];
    const std::uint8_t* up = y > 0 ? out - img.width : nullptr;
    for (int x = 0; x < img.width; ++x) {
      const int a = x > 0 ? out[x - 1] : 0, b = up ? up[x] : 0, c = (up && x > 0) ? up[x - 1] : 0;
      int predicted = 0;
      switch (filter) {
        case 0:
          predicted = 0;
          break;
        case 1:
          predicted = a;
          break;
        case 2:
          predicted = b;
          break;
        case 3:
          predicted = (a + b) / 2;
          break;
        case 4:
          predicted = paeth(a, b, c);
          break;
        default:
          throw InputError(path, 0, "PNG row filter 0..4 (found " + std::to_string(filter) + ")");
      }
      out[x] = static_cast<std::uint8_t>(row[1 + x] + predicted);
    }
  }
  return img;
}

}  // namespace loopscan::io
