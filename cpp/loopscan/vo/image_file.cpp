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

// Width and height from a JPEG's start-of-frame segment, walking the segments through the
// file (EXIF and ICC segments can push it far in); false when there is none before the scan.
bool jpeg_size(std::ifstream& in, int& width, int& height) {
  unsigned char h[9];
  in.seekg(2);  // after FF D8
  while (in.read(reinterpret_cast<char*>(h), 4) && h[0] == 0xFF) {
    const int marker = h[1];
    const std::streamoff len = (std::streamoff(h[2]) << 8) | h[3];
    if (marker == 0xDA || len < 2) return false;  // start of scan: no frame header before it
    const bool sof =
        marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      if (!in.read(reinterpret_cast<char*>(h + 4), 5)) return false;
      height = (h[5] << 8) | h[6];
      width = (h[7] << 8) | h[8];
      return true;
    }
    in.seekg(len - 2, std::ios::cur);
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
    throw io::InputError(path, 0, "a readable image file (PNG or JPEG)");
  }
  if (bytes > io::limits::kMaxImageFileBytes) {
    throw io::InputError(path, 0,
                         "an image file of at most " +
                             std::to_string(io::limits::kMaxImageFileBytes >> 20) + " MiB");
  }
  std::ifstream in(path, std::ios::binary);
  unsigned char magic[8] = {0};
  in.read(reinterpret_cast<char*>(magic), sizeof magic);
  const std::streamsize got = in.gcount();
  if (got == 8 && std::memcmp(magic, "\x89PNG\r\n\x1a\n", 8) == 0) {
    const io::GrayPng png = io::read_png_gray(path);
    cv::Mat image(png.height, png.width, CV_8UC1);
    std::memcpy(image.data, png.pixels.data(), png.pixels.size());
    return image;
  }
  // JPEG through OpenCV once its frame header gives a size within the limits; other formats
  // are refused, since their size could not be checked before decoding.
  in.clear();
  int width = 0, height = 0;
  if (got < 2 || magic[0] != 0xFF || magic[1] != 0xD8) {
    throw io::InputError(path, 0, "a PNG or JPEG image (other formats: convert them first)");
  }
  if (!jpeg_size(in, width, height)) {
    throw io::InputError(path, 0, "a JPEG frame header (SOF) before the image data");
  }
  check_size(path, width, height);
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    throw io::InputError(path, 0, "a readable image (OpenCV: " + e.err + ")");
  }
  if (image.empty()) throw io::InputError(path, 0, "a readable JPEG image");
  check_size(path, image.cols, image.rows);
  return image;
}

}  // namespace loopscan::vo
