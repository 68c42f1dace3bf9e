#include "loopscan/vo/image_file.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <opencv2/imgcodecs.hpp>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/limits.hpp"
#include "loopscan/io/png.hpp"

namespace loopscan::vo {
namespace {

// Width and height from a JPEG's start-of-frame segment; false when none is found in `head`.
bool jpeg_size(const std::string& head, int& width, int& height) {
  const auto* p = reinterpret_cast<const unsigned char*>(head.data());
  std::size_t at = 2;  // after FF D8
  while (at + 9 <= head.size() && p[at] == 0xFF) {
    const int marker = p[at + 1];
    const std::size_t len = (std::size_t(p[at + 2]) << 8) | p[at + 3];
    const bool sof =
        marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      height = (p[at + 5] << 8) | p[at + 6];
      width = (p[at + 7] << 8) | p[at + 8];
      return true;
    }
    if (len < 2) return false;
    at += 2 + len;
  }
  return false;
}

void check_size(const std::string& path, std::int64_t width, std::int64_t height) {
  if (width < 1 || height < 1 || width > io::limits::kMaxImageSide ||
      height > io::limits::kMaxImageSide || width * height > io::limits::kMaxImagePixels) {
    throw io::InputError(path, 0,
                         "an image of 1.." + std::to_string(io::limits::kMaxImageSide) +
                             " px a side and at most " +
                             std::to_string(io::limits::kMaxImagePixels) + " pixels (found " +
                             std::to_string(width) + "x" + std::to_string(height) + ")");
  }
}

}  // namespace

cv::Mat read_gray_image(const std::string& path) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (ec || std::filesystem::is_directory(path)) {
    throw io::InputError(path, 0, "a readable image (PNG, JPEG, ...)");
  }
  if (bytes > io::limits::kMaxImageFileBytes) {
    throw io::InputError(path, 0,
                         "an image file of at most " +
                             std::to_string(io::limits::kMaxImageFileBytes >> 20) + " MiB");
  }
  std::string head(65536, '\0');
  std::ifstream in(path, std::ios::binary);
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (head.size() >= 8 && std::memcmp(head.data(), "\x89PNG\r\n\x1a\n", 8) == 0) {
    const io::GrayPng png = io::read_png_gray(path);
    cv::Mat image(png.height, png.width, CV_8UC1);
    std::memcpy(image.data, png.pixels.data(), png.pixels.size());
    return image;
  }
  int width = 0, height = 0;
  if (head.size() >= 2 && static_cast<unsigned char>(head[0]) == 0xFF &&
      static_cast<unsigned char>(head[1]) == 0xD8 && jpeg_size(head, width, height)) {
    check_size(path, width, height);
  }
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    throw io::InputError(path, 0, "a readable image (OpenCV: " + e.err + ")");
  }
  if (image.empty()) throw io::InputError(path, 0, "a readable image (PNG, JPEG, ...)");
  check_size(path, image.cols, image.rows);
  return image;
}

}  // namespace loopscan::vo
