// Raw stereo cameras (EuRoC layout, ../shared/data/real/euroc-v101-micro): calibration, the
// rectification (epipolar lines become image rows), the sequence, malformed sensor.yaml files.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "loopscan/io/errors.hpp"
#include "loopscan/vo/euroc.hpp"
#include "loopscan/vo/image_file.hpp"
#include "support/input_errors.hpp"
#include "support/test_support.hpp"

namespace loopscan::vo {
namespace {
namespace fs = std::filesystem;

fs::path micro() { return fs::path(test::shared_dir()) / "data/real/euroc-v101-micro"; }

// Median |row difference| of corners tracked from the left image into the right one.
double median_row_offset(const cv::Mat& left, const cv::Mat& right) {
  std::vector<cv::Point2f> a, b;
  cv::goodFeaturesToTrack(left, a, 300, 0.01, 10);
  std::vector<unsigned char> ok;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(left, right, a, b, ok, err, cv::Size(21, 21), 3);
  std::vector<double> dy;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (ok[i] && b[i].x < a[i].x) dy.push_back(std::abs(b[i].y - a[i].y));
  }
  EXPECT_GT(dy.size(), 50u);
  std::nth_element(dy.begin(), dy.begin() + dy.size() / 2, dy.end());
  return dy[dy.size() / 2];
}

TEST(Euroc, RectificationMakesEpipolarLinesRows) {
  LOOPSCAN_SKIP_WITHOUT_SHARED(fs::exists(micro() / "mav0"), micro());
  const CameraCalibration c0 = read_camera_yaml((micro() / "mav0/cam0/sensor.yaml").string());
  EXPECT_NEAR(c0.fx, 458.654, 1e-9);
  EXPECT_EQ(c0.width, 752);
  EXPECT_NEAR(c0.distortion[0], -0.28340811, 1e-12);
  const EurocSequence s = open_euroc_sequence(micro().string());
  ASSERT_EQ(s.files.frames(), 95u);
  EXPECT_NEAR(s.files.times[1] - s.files.times[0], 0.05, 1e-3);  // 20 Hz
  // The V1 rig: an 11 cm baseline; the rectified focal length near the raw one.
  EXPECT_NEAR(s.rectification.calib.baseline_m, 0.110, 0.002);
  EXPECT_NEAR(s.rectification.calib.fx, 440, 40);
  cv::Mat left = read_gray_image(s.files.left(10)), right = read_gray_image(s.files.right(10));
  const double raw = median_row_offset(left, right);
  s.rectification.apply(left, right);
  const double rectified = median_row_offset(left, right);
  std::printf("median |dy| raw %.3f px, rectified %.3f px\n", raw, rectified);
  EXPECT_LT(rectified, 0.3);
  EXPECT_LT(rectified, raw);
}

TEST(Euroc, MalformedCalibrationsNameTheFileAndKey) {
  const fs::path d = test::temp_path("euroc_yaml");
  fs::create_directories(d);
  const std::string good =
      "%YAML:1.0\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, "
      "0, 1]\nresolution: [752, 480]\ncamera_model: pinhole\nintrinsics: [458.6, 457.3, 367.2, "
      "248.4]\ndistortion_model: radial-tangential\ndistortion_coefficients: [-0.28, 0.07, 0.0, "
      "0.0]\n";
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(d / name) << text;
    return (d / name).string();
  };
  EXPECT_NEAR(read_camera_yaml(write("ok.yaml", good)).fx, 458.6, 1e-12);
  auto replace = [&](std::string from, std::string to) {
    std::string t = good;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  const std::pair<std::string, std::string> bad[] = {
      {write("negf.yaml", replace("458.6", "-458.6")), "focal lengths"},
      {write("short.yaml", replace("367.2, 248.4", "367.2")), "intrinsics: 4 finite numbers"},
      {write("fisheye.yaml", replace("pinhole", "omni")), "camera_model: pinhole"},
      {write("equi.yaml", replace("radial-tangential", "equidistant")), "radial-tangential"},
      {write("tbs.yaml", replace("data: [1, 0", "data: [2, 0")), "T_BS"},
      {write("trunc.yaml", good.substr(0, 60)), "trunc.yaml"}};
  for (const auto& [path, fragment] : bad)
    test::expect_input_error([](const std::string& p) { read_camera_yaml(p); }, path, fragment);
}

}  // namespace
}  // namespace loopscan::vo
