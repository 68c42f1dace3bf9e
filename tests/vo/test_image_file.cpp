// read_gray_image: PNGs through loopscan's decoder agree with OpenCV's IMREAD_GRAYSCALE (the
// oracle) for every kind OpenCV writes; JPEGs go through OpenCV; bad files are InputErrors
// naming the file, without OpenCV's or libpng's messages.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "loopscan/io/errors.hpp"
#include "loopscan/vo/image_file.hpp"
#include "support/png_encoder.hpp"

namespace loopscan {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("loopscan_image_" + std::to_string(::getpid()) + name);
}

cv::Mat random_image(int rows, int cols, int type, unsigned seed) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0, CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256);
  return m;
}

TEST(ImageFile, PngDecoderAgreesWithOpenCvOnEveryKindOpenCvWrites) {
  const fs::path p = temp_file("a.png");
  struct Case {
    int type;
    const char* name;
  };
  for (const Case c : {Case{CV_8UC1, "gray8"}, Case{CV_16UC1, "gray16"}, Case{CV_8UC3, "bgr8"},
                       Case{CV_16UC3, "bgr16"}, Case{CV_8UC4, "bgra8"}}) {
    const cv::Mat written = random_image(23, 41, c.type, 7);
    ASSERT_TRUE(cv::imwrite(p.string(), written)) << c.name;
    const cv::Mat ours = vo::read_gray_image(p.string());
    const cv::Mat theirs = cv::imread(p.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(ours.type(), CV_8UC1) << c.name;
    ASSERT_EQ(ours.size(), theirs.size()) << c.name;
    double worst = 0;  // the same conversion, bit for bit
    cv::minMaxLoc(cv::abs(ours - theirs) + cv::abs(theirs - ours), nullptr, &worst);
    EXPECT_EQ(worst, 0.0) << c.name << ": " << cv::countNonZero(ours != theirs)
                          << " differ";  // the same weights; rounding may differ by one level
    if (c.type == CV_8UC1) {
      EXPECT_EQ(cv::countNonZero(ours != written), 0);
    }
  }
  fs::remove(p);
}

TEST(ImageFile, JpegGoesThroughOpenCv) {
  const fs::path p = temp_file("b.jpg");
  const cv::Mat written = random_image(16, 24, CV_8UC3, 3);
  ASSERT_TRUE(cv::imwrite(p.string(), written));
  const cv::Mat ours = vo::read_gray_image(p.string());
  EXPECT_EQ(cv::countNonZero(ours != cv::imread(p.string(), cv::IMREAD_GRAYSCALE)), 0);
  fs::remove(p);
}

std::string error_of(const std::string& bytes, const std::string& suffix) {
  const fs::path p = temp_file("c" + suffix);
  std::ofstream(p, std::ios::binary) << bytes;
  std::string message = "loaded";
  try {
    vo::read_gray_image(p.string());
  } catch (const io::InputError& e) {
    message = e.what();
    EXPECT_NE(message.find(p.string()), std::string::npos) << message;
  }
  fs::remove(p);
  return message;
}

TEST(ImageFile, HugeDamagedOrMissingImagesAreInputErrorsNamingTheFile) {
  // 16384 x 8192 is within the side limit but beyond 2^26 pixels.
  EXPECT_NE(error_of(test::png_announcing(16384, 8192), ".png").find("at most 67108864 pixels"),
            std::string::npos);
  // A 65535 x 65535 PNG header (OpenCV would throw an assertion naming no file).
  EXPECT_NE(error_of(test::png_announcing(65535, 65535), ".png").find("65535x65535"),
            std::string::npos);
  // A JPEG whose start-of-frame announces 60000 x 60000: refused before OpenCV decodes.
  std::string sof("\xFF\xD8\xFF\xC0\x00\x11\x08\xEA\x60\xEA\x60\x03", 12);
  sof += std::string(15, '\x01');
  EXPECT_NE(error_of(sof, ".jpg").find("60000x60000"), std::string::npos);
  EXPECT_NE(error_of("not an image at all", ".jpg").find("a PNG or JPEG image"), std::string::npos);
  EXPECT_NE(error_of("BM6\0\0\0", ".bmp").find("a PNG or JPEG image"), std::string::npos);
  // The frame header found behind 100 KB of an APP segment (EXIF, ICC): still checked.
  std::string app("\xFF\xD8\xFF\xE1\xFF\xFF", 6);
  app += std::string(0xFFFF - 2, '\0');
  app += std::string("\xFF\xE2\xFF\xFF", 4) + std::string(0xFFFF - 2, '\0');
  EXPECT_NE(error_of(app + sof.substr(2), ".jpg").find("60000x60000"), std::string::npos);
  EXPECT_NE(error_of(app + "\xFF\xDA\x00\x08", ".jpg").find("frame header"), std::string::npos);
  EXPECT_NE(error_of("\x89PNG\r\n\x1a\n", ".png").find("truncated"), std::string::npos);
  EXPECT_THROW(vo::read_gray_image("/nonexistent/x.png"), io::InputError);
}

}  // namespace
}  // namespace loopscan
