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

// One keyframe as streaming callers give it: id, world-to-camera (3, 4) and its points (N, 4)
// x y z gray in the world frame.
KeyframePose keyframe_pose(int keyframe, const DoubleArray& T_cam_world);
std::vector<IdPoint> keyframe_points(int keyframe, const DoubleArray& points);

// (N, 4) x y z gray -> one scan (camera frame).
Cloud to_cloud(const DoubleArray& xyz_gray);

// An (N, 3) float64 array of positions and back.
std::vector<Eigen::Vector3d> to_positions(const DoubleArray& positions, const std::string& name);
py::array_t<double> from_positions(const std::vector<Eigen::Vector3d>& positions);

// A rigid transform as a 4x4 float64 array.
py::array_t<double> from_isometry(const Eigen::Isometry3d& T);

// A row-major matrix as a new numpy array (copied: Eigen's default storage is column-major).
py::array_t<double> from_matrix(const Eigen::MatrixXd& m);
Eigen::MatrixXd to_matrix(const DoubleArray& a, const std::string& name);

Method parse_method_name(const std::string& name);
Mode parse_mode_name(const std::string& name);

}  // namespace loopscan::python
