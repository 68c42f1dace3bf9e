// Stereo VO on numpy images, the KITTI calibration reader and the gray-image reader.
#include <cstring>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "loopscan/io/kitti_sequence.hpp"
#include "loopscan/vo/image_file.hpp"
#include "loopscan/vo/stereo_vo.hpp"

namespace loopscan::python {

namespace {

using U8Array = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>;

// The image as a cv::Mat owning a copy: the VO keeps earlier frames after process() returns.
cv::Mat to_mat(const U8Array& image, const std::string& name, const vo::StereoIntrinsics& cam) {
  require_shape(image, name, {cam.height, cam.width}, "an 8-bit gray image of the camera's size");
  return cv::Mat(cam.height, cam.width, CV_8UC1, const_cast<std::uint8_t*>(image.data())).clone();
}

}  // namespace

void bind_vo(py::module_& m) {
  using vo::FrameResult;
  using vo::StereoVo;
  py::class_<FrameResult>(m, "FrameResult", "The VO's answer for one frame.")
      .def_readonly("frame", &FrameResult::frame)
      .def_property_readonly(
          "T_world_cam", [](const FrameResult& r) { return from_isometry(r.T_world_cam); },
          "4x4 camera-to-world, online estimate")
      .def_readonly("keyframe", &FrameResult::keyframe)
      .def_readonly("reset", &FrameResult::reset)
      .def_readonly("tracked", &FrameResult::tracked)
      .def_readonly("inliers", &FrameResult::inliers);
  py::class_<StereoVo>(m, "StereoVo", "Stereo visual odometry on rectified 8-bit image pairs.")
      .def(py::init([](double fx, double fy, double cx, double cy, double baseline_m, int width,
                       int height, int points_per_keyframe) {
             vo::StereoIntrinsics c{fx, fy, cx, cy, baseline_m, width, height};
             vo::VoConfig config;
             config.points_per_keyframe = points_per_keyframe;
             return StereoVo(c, config);
           }),
           py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("baseline_m"),
           py::arg("width"), py::arg("height"), py::arg("points_per_keyframe") = 1000)
      .def(
          "process",
          [](StereoVo& v, int frame, const U8Array& left, const U8Array& right) {
            const vo::StereoIntrinsics& cam = v.camera();
            const cv::Mat l = to_mat(left, "left", cam), r = to_mat(right, "right", cam);
            py::gil_scoped_release release;
            return v.process(frame, l, r);
          },
          py::arg("frame"), py::arg("left"), py::arg("right"),
          "Next frame (ids increasing): rectified left/right uint8 images (height, width).")
      .def("finish", &StereoVo::finish, py::call_guard<py::gil_scoped_release>())
      .def(
          "keyframes",
          [](const StereoVo& v) {
            py::list out;
            for (const vo::FinishedKeyframe& k : v.finished_keyframes()) {
              const py::tuple ids_xyz = from_points(vo::world_points(k));
              out.append(
                  py::make_tuple(k.frame, from_isometry(k.T_world_cam), k.reset, ids_xyz[1]));
            }
            return out;
          },
          "Finished keyframes: (frame, T_world_cam 4x4, reset, points (N, 4) world x y z gray).")
      .def(
          "trajectory", [](const StereoVo& v) { return from_isometries(v.trajectory()); },
          "Every processed frame's camera-to-world pose (N, 4, 4), on its keyframe's final pose.");
  m.def(
      "read_kitti_calib",
      [](const std::string& path) {
        const io::KittiCalib c = io::read_kitti_calib(path);
        py::dict d;
        d["fx"] = c.fx;
        d["fy"] = c.fy;
        d["cx"] = c.cx;
        d["cy"] = c.cy;
        d["baseline_m"] = c.baseline_m;
        return d;
      },
      py::arg("path"), "KITTI calib.txt (P0, P1) -> dict fx, fy, cx, cy, baseline_m.");
  m.def(
      "read_gray_image",
      [](const std::string& path) {
        const cv::Mat img = vo::read_gray_image(path);
        py::array_t<std::uint8_t> out(
            {static_cast<py::ssize_t>(img.rows), static_cast<py::ssize_t>(img.cols)});
        for (int r = 0; r < img.rows; ++r)
          std::memcpy(out.mutable_data(r, 0), img.ptr(r), static_cast<std::size_t>(img.cols));
        return out;
      },
      py::arg("path"), "A PNG or JPEG as an 8-bit gray image (height, width), uint8.");
}

}  // namespace loopscan::python
