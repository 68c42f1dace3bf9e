#include "loopscan/vo/euroc.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgproc.hpp>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/line_reader.hpp"

namespace loopscan::vo {
namespace {
namespace fs = std::filesystem;

std::vector<double> numbers(const std::string& path, const cv::FileNode& node, const char* key,
                            std::size_t n) {
  std::vector<double> v;
  if (node.isSeq()) {
    for (const cv::FileNode& x : node) v.push_back(static_cast<double>(x));
  }
  if (v.size() != n || !std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }))
    throw io::InputError(path, 0, std::string(key) + ": " + std::to_string(n) + " finite numbers");
  return v;
}

std::string text(const cv::FileNode& node) {
  return node.isString() ? static_cast<std::string>(node) : std::string();
}

std::string mav0_of(const std::string& dir) {
  return fs::exists(fs::path(dir) / "mav0") ? (fs::path(dir) / "mav0").string() : dir;
}

}  // namespace

CameraCalibration read_camera_yaml(const std::string& path) {
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ)) throw io::InputError(path, 0, "a readable file");
  } catch (const cv::Exception& e) {
    throw io::InputError(path, 0, std::string("a YAML camera description (") + e.err + ")");
  }
  const std::string model = text(fs["camera_model"]), dist = text(fs["distortion_model"]);
  if (model != "pinhole") throw io::InputError(path, 0, "camera_model: pinhole");
  if (dist != "radial-tangential" && dist != "radtan")
    throw io::InputError(path, 0, "distortion_model: radial-tangential");
  CameraCalibration c;
  const std::vector<double> k = numbers(path, fs["intrinsics"], "intrinsics", 4);
  c.fx = k[0], c.fy = k[1], c.cx = k[2], c.cy = k[3];
  if (!(c.fx > 0 && c.fy > 0))
    throw io::InputError(path, 0, "intrinsics: focal lengths fu, fv > 0");
  const std::vector<double> d =
      numbers(path, fs["distortion_coefficients"], "distortion_coefficients", 4);
  std::copy(d.begin(), d.end(), c.distortion.begin());
  const std::vector<double> r = numbers(path, fs["resolution"], "resolution", 2);
  c.width = static_cast<int>(r[0]), c.height = static_cast<int>(r[1]);
  if (c.width < 16 || c.height < 16 || c.width > 32768 || c.height > 32768)
    throw io::InputError(path, 0, "resolution: width height in [16, 32768]");
  const std::vector<double> t = numbers(path, fs["T_BS"]["data"], "T_BS.data", 16);
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = t[i];
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 ||
      R.determinant() < 0 || m.row(3).cwiseAbs().sum() - 1.0 > 1e-9 || m(3, 3) != 1.0)
    throw io::InputError(path, 0, "T_BS: a rigid transform (rotation + translation)");
  c.T_body_camera.linear() = R;
  c.T_body_camera.translation() = m.topRightCorner<3, 1>();
  return c;
}

void StereoRectification::apply(cv::Mat& left, cv::Mat& right) const {
  cv::Mat l, r;
  cv::remap(left, l, left_x, left_y, cv::INTER_LINEAR);
  cv::remap(right, r, right_x, right_y, cv::INTER_LINEAR);
  left = l;
  right = r;
}

StereoRectification rectify_stereo(const CameraCalibration& a, const CameraCalibration& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("stereo cameras of different resolutions");
  // OpenCV wants the right camera's pose seen from the left: x_right = R x_left + T.
  const Eigen::Isometry3d right_from_left = b.T_body_camera.inverse() * a.T_body_camera;
  if (right_from_left.translation().norm() < 1e-3)
    throw std::invalid_argument("stereo cameras without a baseline");
  auto K = [](const CameraCalibration& c) {
    return cv::Matx33d(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  };
  auto D = [](const CameraCalibration& c) {
    return cv::Vec4d(c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3]);
  };
  cv::Matx33d R;
  cv::Vec3d T;
  for (int i = 0; i < 3; ++i) {
    T[i] = right_from_left.translation()(i);
    for (int j = 0; j < 3; ++j) R(i, j) = right_from_left.linear()(i, j);
  }
  const cv::Size size(a.width, a.height);
  cv::Mat R0, R1, P0, P1, Q;
  // alpha 0: only valid pixels; the principal points coincide (zero disparity at infinity).
  cv::stereoRectify(K(a), D(a), K(b), D(b), size, R, T, R0, R1, P0, P1, Q, cv::CALIB_ZERO_DISPARITY,
                    0.0, size);
  StereoRectification s;
  cv::initUndistortRectifyMap(K(a), D(a), R0, P0, size, CV_32FC1, s.left_x, s.left_y);
  cv::initUndistortRectifyMap(K(b), D(b), R1, P1, size, CV_32FC1, s.right_x, s.right_y);
  s.calib.fx = P0.at<double>(0, 0);
  s.calib.fy = P0.at<double>(1, 1);
  s.calib.cx = P0.at<double>(0, 2);
  s.calib.cy = P0.at<double>(1, 2);
  s.calib.baseline_m = -P1.at<double>(0, 3) / P1.at<double>(0, 0);
  if (!(s.calib.baseline_m > 0))
    throw std::invalid_argument("stereo cameras: the second camera must be right of the first");
  // x_rect = R0 x_left: the rectified camera in the body frame is T_BS * [R0^T | 0].
  Eigen::Matrix3d r0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r0(i, j) = R0.at<double>(i, j);
  Eigen::Isometry3d left_from_rect = Eigen::Isometry3d::Identity();
  left_from_rect.linear() = r0.transpose();
  s.T_body_rectified = a.T_body_camera * left_from_rect;
  return s;
}

bool is_euroc_layout(const std::string& dir) {
  const fs::path m = mav0_of(dir);
  return fs::exists(m / "cam0" / "data.csv") && fs::exists(m / "cam1" / "data.csv");
}

EurocSequence open_euroc_sequence(const std::string& dir) {
  const fs::path m = mav0_of(dir);
  if (!is_euroc_layout(dir))
    throw io::InputError(dir, 0, "an EuRoC folder: mav0/cam0/data.csv and mav0/cam1/data.csv");
  EurocSequence s;
  s.rectification = rectify_stereo(read_camera_yaml((m / "cam0" / "sensor.yaml").string()),
                                   read_camera_yaml((m / "cam1" / "sensor.yaml").string()));
  s.files.dir = dir;
  s.files.calib = s.rectification.calib;
  const std::string csv = (m / "cam0" / "data.csv").string();
  io::LineReader reader(csv);
  std::string_view line;
  while (io::next_data_line(reader, line)) {
    if (!line.empty() && line.front() == '#') continue;
    const std::size_t comma = line.find(',');
    std::string name(comma == std::string_view::npos ? "" : line.substr(comma + 1));
    while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
    while (!name.empty() && name.front() == ' ') name.erase(name.begin());
    char* end = nullptr;
    const std::string stamp(line.substr(0, comma));
    const double ns = std::strtod(stamp.c_str(), &end);
    if (comma == std::string_view::npos || name.empty() || end == stamp.c_str() || *end != '\0' ||
        !(ns >= 0))
      throw io::InputError(csv, reader.line_number(), "timestamp_ns,filename");
    const fs::path left = m / "cam0" / "data" / name, right = m / "cam1" / "data" / name;
    if (!fs::exists(left)) throw io::InputError(left.string(), 0, "the image data.csv names");
    if (!fs::exists(right)) continue;  // the pair is incomplete: the frame is left out
    const double t = ns * 1e-9;
    if (!s.files.times.empty() && t <= s.files.times.back())
      throw io::InputError(csv, reader.line_number(), "increasing timestamps");
    s.files.times.push_back(t);
    s.files.left_files.push_back(left.string());
    s.files.right_files.push_back(right.string());
  }
  if (s.files.times.empty()) throw io::InputError(csv, 0, "at least one stereo pair");
  return s;
}

}  // namespace loopscan::vo
