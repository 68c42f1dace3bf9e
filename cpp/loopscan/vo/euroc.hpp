#pragma once
// Raw (distorted, unrectified) stereo cameras in the EuRoC layout: mav0/cam0 and mav0/cam1, each
// with data/*.png, data.csv (`timestamp_ns,filename`) and sensor.yaml (pinhole intrinsics,
// radial-tangential distortion, resolution, T_BS = the camera in the body frame). The same
// sensor.yaml describes a user's own camera. Rectified with OpenCV's stereoRectify + remap.
#include <array>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "loopscan/io/kitti_sequence.hpp"

namespace loopscan::vo {

struct CameraCalibration {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<double, 4> distortion{};  // k1 k2 p1 p2 (radial-tangential)
  int width = 0, height = 0;
  Eigen::Isometry3d T_body_camera = Eigen::Isometry3d::Identity();  // EuRoC's T_BS
};

// Throws io::InputError naming the file and the key on a missing or invalid entry (unknown
// camera or distortion model, a focal length <= 0, a T_BS that is not rigid).
CameraCalibration read_camera_yaml(const std::string& path);

struct StereoRectification {
  cv::Mat left_x, left_y, right_x, right_y;  // remap tables, rectified pixel -> raw pixel
  io::KittiCalib calib;                      // the rectified pinhole pair (baseline in metres)
  Eigen::Isometry3d T_body_rectified = Eigen::Isometry3d::Identity();  // rectified left camera
  // Rectifies a raw pair in place (bilinear).
  void apply(cv::Mat& left, cv::Mat& right) const;
};

// Throws std::invalid_argument when the two cameras differ in size or share no baseline.
StereoRectification rectify_stereo(const CameraCalibration& left, const CameraCalibration& right);

struct EurocSequence {
  io::KittiSequence files;  // frames paired by file name, times from data.csv, rectified calib
  StereoRectification rectification;
};

// `dir` holds mav0/ (or is mav0/). Throws io::InputError naming the file on a malformed
// data.csv, a missing image or calibration.
EurocSequence open_euroc_sequence(const std::string& dir);
bool is_euroc_layout(const std::string& dir);

}  // namespace loopscan::vo
