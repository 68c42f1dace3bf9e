// ORB-SLAM2 stereo settings (`--calib`): the real KITTI file, and every kind of bad value as
// an InputError with file and line (exit code 2 on the CLI).
#include <gtest/gtest.h>

#include <filesystem>

#include "loopscan/io/camera_settings.hpp"
#include "support/io_fixture.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

using test::error_of;
using test::has;
using CameraSettings = test::IoFixture;

TEST_F(CameraSettings, ReadsTheKittiYaml) {
  const std::string path = test::shared_dir() + "/data/kitti/calib/KITTI04-12.yaml";
  LOOPSCAN_SKIP_WITHOUT_SHARED(std::filesystem::exists(path), path);
  const io::StereoSettings c = io::read_orbslam_stereo(path);
  EXPECT_EQ(Eigen::Vector4d(c.fx, c.fy, c.cx, c.cy),
            Eigen::Vector4d(707.0912, 707.0912, 601.8873, 183.1104));
  EXPECT_EQ(Eigen::Vector3d(c.width, c.height, c.bf), Eigen::Vector3d(1241, 376, 379.8145));
}

TEST_F(CameraSettings, MissingKeysAndBadValuesNameFileAndLine) {
  const std::string body =
      "%YAML:1.0\n# comment\nCamera.fx: 700.5\nCamera.fy: 700.5\nCamera.cx: 600\n"
      "Camera.cy: 180  # principal point\nCamera.width: 1241\nCamera.height: 376\n"
      "Camera.RGB: 1\nLeftMatrix: !!opencv-matrix\n   rows: 3\n";
  const auto read = [](auto p) { io::read_orbslam_stereo(p); };
  expect_bad(read, body, 0, "`Camera.bf: <value>`");
  expect_bad(read, body + "Camera.bf: 3x\n", 12, "Camera.bf: a number");
  expect_bad(read, body + "Camera.bf: nan\n", 12, "Camera.bf");
  expect_bad(read, body + "Camera.bf: -380\n", 12, "in [0.001, 1e+07]");
  expect_bad(read, body + "Camera.bf: 1e308\n", 12, "Camera.bf");
  std::string wide = body;
  wide.replace(wide.find("1241"), 4, "65536");
  expect_bad(read, wide + "Camera.bf: 380\n", 7, "Camera.width: a number in [1, 32768]");
  std::string huge = body;
  huge.replace(huge.find("1241"), 4, "32768").replace(huge.find("376"), 3, "32768");
  expect_bad(read, huge + "Camera.bf: 380\n", 0, "at most 67108864 pixels");
  std::string half = body;
  half.replace(half.find("376"), 3, "375.5");
  expect_bad(read, half + "Camera.bf: 380\n", 8, "whole number");
  expect_bad(read, "Camera.fx 700\n", 1, "`key: value`");
  const io::StereoSettings ok =
      io::read_orbslam_stereo(file("ok.yaml", body + "Camera.bf: 380.0\n"));
  EXPECT_EQ(ok.bf, 380.0);
  EXPECT_EQ(ok.cy, 180.0);
  EXPECT_TRUE(has(error_of([&] { read((dir_ / "absent.yaml").string()); }), "a readable file"));
}

}  // namespace
}  // namespace loopscan
