#pragma once
// numpy <-> loopscan value types. Arrays are checked for shape and dtype first (a clear
// ValueError naming the argument), then read in C++: no per-point Python code.
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Geometry>

#include "loopscan/core/signature.hpp"
#include "loopscan/core/types.hpp"

namespace loopscan::python {

namespace py = pybind11;

// float64, C-contiguous (converted if needed, e.g. from float32 or a slice).
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<int, py::array::c_style | py::array::forcecast>;

// Throws ValueError "<name>: expected an array of shape (N, 4) ..., got (...)".
void require_shape(const py::array& a, const std::string& name, std::vector<py::ssize_t> shape,
                   const std::string& meaning);

// (ids (K,), T_cam_world (K, 3, 4)) <-> keyframe poses.
std::vector<KeyframePose> to_poses(const IntArray& ids, const DoubleArray& T_cam_world);
py::tuple from_poses(const std::vector<KeyframePose>& poses);

// (ids (N,), xyz_gray (N, 4)) <-> VO points (world frame, tagged with their keyframe).
std::vector<IdPoint> to_points(const IntArray& ids, const DoubleArray& xyz_gray);
py::tuple from_points(const std::vector<IdPoint>& points);

// Places as Python sees them: lists and arrays made once, not on every attribute access.
struct Places {
  py::list signatures;  // float64 (rows, values) each
  py::array_t<int> keyframe_ids;
  py::array_t<double> frames;  // (P, 3, 3): descriptor axes in the camera frame (rows = axes)
};
Places places_of(const std::vector<Signature>& signatures, const std::vector<int>& keyframe_ids,
                 const std::vector<Eigen::Matrix3d>& frames);

// The attributes every set of places has: signatures, keyframe_ids, frames, len().
template <typename T, typename Class>
void bind_places(Class& cls) {
  cls.def_property_readonly(
         "signatures", [](const T& s) { return s.places.signatures; },
         "list of float64 arrays (rows, values): rows = versions of the place (row 0: itself)")
      .def_property_readonly(
          "keyframe_ids", [](const T& s) { return s.places.keyframe_ids; },
          "int array (P,): the keyframe of each place")
      .def_property_readonly(
          "frames", [](const T& s) { return s.places.frames; },
          "float64 (P, 3, 3): each descriptor's axes in its camera frame (Database.add's frame)")
      .def("__len__", [](const T& s) { return py::len(s.places.signatures); });
}

// A fixed-size matrix (e.g. a 3x4 pose, a 3x3 frame) from a checked (R, C) array.
template <int R, int C>
Eigen::Matrix<double, R, C> to_fixed(const DoubleArray& a, const std::string& name,
                                     const std::string& meaning) {
  require_shape(a, name, {R, C}, meaning);
  return Eigen::Map<const Eigen::Matrix<double, R, C, Eigen::RowMajor>>(a.data());
}

// One keyframe as streaming callers give it: id, world-to-camera (3, 4) and its points (N, 4)
// x y z gray in the world frame.
KeyframePose keyframe_pose(int keyframe, const DoubleArray& T_cam_world);
std::vector<IdPoint> keyframe_points(int keyframe, const DoubleArray& points);

// Streamer::add_keyframe (Recognizer, LoopCloser) on arrays, the GIL released while it works.
template <typename Streamer>
auto add_keyframe_arrays(Streamer& streamer, int keyframe, const DoubleArray& T_cam_world,
                         const DoubleArray& points, bool reset) {
  const KeyframePose kf = keyframe_pose(keyframe, T_cam_world);
  const std::vector<IdPoint> pts = keyframe_points(keyframe, points);
  py::gil_scoped_release release;
  return streamer.add_keyframe(kf, pts.data(), pts.size(), reset);
}

// (N, 4) x y z gray -> one scan (camera frame).
Cloud to_cloud(const DoubleArray& xyz_gray);

// An (N, 3) float64 array of positions and back.
std::vector<Eigen::Vector3d> to_positions(const DoubleArray& positions, const std::string& name);
py::array_t<double> from_positions(const std::vector<Eigen::Vector3d>& positions);

// A rigid transform as a 4x4 float64 array; several as (N, 4, 4).
py::array_t<double> from_isometry(const Eigen::Isometry3d& T);
py::array_t<double> from_isometries(const std::vector<Eigen::Isometry3d>& poses);

// A row-major matrix as a new numpy array (copied: Eigen's default storage is column-major).
py::array_t<double> from_matrix(const Eigen::MatrixXd& m);
Eigen::MatrixXd to_matrix(const DoubleArray& a, const std::string& name);

Method parse_method_name(const std::string& name);
Mode parse_mode_name(const std::string& name);

}  // namespace loopscan::python
