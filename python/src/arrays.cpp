#include "arrays.hpp"

#include <stdexcept>

#include "loopscan/core/signature.hpp"

namespace loopscan::python {

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

}  // namespace

void require_shape(const py::array& a, const std::string& name, std::vector<py::ssize_t> shape,
                   const std::string& meaning) {
  bool ok = a.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t d = 0; ok && d < shape.size(); ++d)
    ok = shape[d] < 0 || a.shape(static_cast<py::ssize_t>(d)) == shape[d];
  if (ok) return;
  std::string want = "(";
  for (std::size_t d = 0; d < shape.size(); ++d)
    want += (d ? ", " : "") + (shape[d] < 0 ? std::string("N") : std::to_string(shape[d]));
  want += shape.size() == 1 ? ",)" : ")";
  throw py::value_error(name + ": expected an array of shape " + want + " (" + meaning +
                        "), got shape " + shape_text(a));
}

std::vector<KeyframePose> to_poses(const IntArray& ids, const DoubleArray& T) {
  require_shape(ids, "keyframe ids", {-1}, "one integer id per keyframe");
  require_shape(T, "T_cam_world", {ids.shape(0), 3, 4}, "one 3x4 world-to-camera pose per id");
  std::vector<KeyframePose> poses(static_cast<std::size_t>(ids.shape(0)));
  const auto id = ids.unchecked<1>();
  const auto t = T.unchecked<3>();
  for (py::ssize_t k = 0; k < ids.shape(0); ++k) {
    poses[k].id = id(k);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) poses[k].T_cam_world(r, c) = t(k, r, c);
  }
  return poses;
}

py::tuple from_poses(const std::vector<KeyframePose>& poses) {
  const auto n = static_cast<py::ssize_t>(poses.size());
  py::array_t<int> ids(n);
  py::array_t<double> T({n, py::ssize_t(3), py::ssize_t(4)});
  auto id = ids.mutable_unchecked<1>();
  auto t = T.mutable_unchecked<3>();
  for (py::ssize_t k = 0; k < n; ++k) {
    id(k) = poses[k].id;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) t(k, r, c) = poses[k].T_cam_world(r, c);
  }
  return py::make_tuple(ids, T);
}

std::vector<IdPoint> to_points(const IntArray& ids, const DoubleArray& xyz_gray) {
  require_shape(ids, "point ids", {-1}, "the keyframe id of each point");
  require_shape(xyz_gray, "points", {ids.shape(0), 4}, "x y z gray per point, world frame");
  std::vector<IdPoint> out(static_cast<std::size_t>(ids.shape(0)));
  const auto id = ids.unchecked<1>();
  const auto p = xyz_gray.unchecked<2>();
  for (py::ssize_t i = 0; i < ids.shape(0); ++i) {
    out[i].id = id(i);
    out[i].p_world = {p(i, 0), p(i, 1), p(i, 2)};
    out[i].intensity = static_cast<float>(p(i, 3));
  }
  return out;
}

py::tuple from_points(const std::vector<IdPoint>& points) {
  const auto n = static_cast<py::ssize_t>(points.size());
  py::array_t<int> ids(n);
  py::array_t<double> xyz({n, py::ssize_t(4)});
  auto id = ids.mutable_unchecked<1>();
  auto p = xyz.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    id(i) = points[i].id;
    for (int c = 0; c < 3; ++c) p(i, c) = points[i].p_world[c];
    p(i, 3) = points[i].intensity;
  }
  return py::make_tuple(ids, xyz);
}

KeyframePose keyframe_pose(int keyframe, const DoubleArray& T_cam_world) {
  return {keyframe,
          to_fixed<3, 4>(T_cam_world, "T_cam_world", "world-to-camera transform, top three rows")};
}

std::vector<IdPoint> keyframe_points(int keyframe, const DoubleArray& points) {
  require_shape(points, "points", {-1, 4}, "x y z gray per point, world frame");
  std::vector<IdPoint> pts(static_cast<std::size_t>(points.shape(0)));
  const auto p = points.unchecked<2>();
  for (py::ssize_t i = 0; i < points.shape(0); ++i)
    pts[i] = {keyframe, {p(i, 0), p(i, 1), p(i, 2)}, static_cast<float>(p(i, 3))};
  return pts;
}

Cloud to_cloud(const DoubleArray& xyz_gray) {
  require_shape(xyz_gray, "points", {-1, 4}, "x y z gray per point, camera frame");
  Cloud cloud(static_cast<std::size_t>(xyz_gray.shape(0)));
  const auto p = xyz_gray.unchecked<2>();
  for (py::ssize_t i = 0; i < xyz_gray.shape(0); ++i) {
    cloud[i].p = {p(i, 0), p(i, 1), p(i, 2)};
    cloud[i].intensity = static_cast<float>(p(i, 3));
  }
  return cloud;
}

std::vector<Eigen::Vector3d> to_positions(const DoubleArray& positions, const std::string& name) {
  require_shape(positions, name, {-1, 3}, "x y z per place");
  std::vector<Eigen::Vector3d> out(static_cast<std::size_t>(positions.shape(0)));
  const auto p = positions.unchecked<2>();
  for (py::ssize_t i = 0; i < positions.shape(0); ++i) out[i] = {p(i, 0), p(i, 1), p(i, 2)};
  return out;
}

py::array_t<double> from_positions(const std::vector<Eigen::Vector3d>& positions) {
  py::array_t<double> out({static_cast<py::ssize_t>(positions.size()), py::ssize_t(3)});
  auto p = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < positions.size(); ++i)
    for (int c = 0; c < 3; ++c) p(static_cast<py::ssize_t>(i), c) = positions[i][c];
  return out;
}

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

py::array_t<double> from_matrix(const Eigen::MatrixXd& m) {
  py::array_t<double> out({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  Eigen::Map<RowMajor>(out.mutable_data(), m.rows(), m.cols()) = m;  // one vectorised copy
  return out;
}

Eigen::MatrixXd to_matrix(const DoubleArray& a, const std::string& name) {
  require_shape(a, name, {-1, -1}, "one signature: rows x values");
  return Eigen::Map<const RowMajor>(a.data(), a.shape(0), a.shape(1));
}

Places places_of(const std::vector<Signature>& signatures, const std::vector<int>& keyframe_ids,
                 const std::vector<Eigen::Matrix3d>& frames) {
  Places p;
  for (const Signature& s : signatures) p.signatures.append(from_matrix(s));
  p.keyframe_ids =
      py::array_t<int>(static_cast<py::ssize_t>(keyframe_ids.size()), keyframe_ids.data());
  p.frames = py::array_t<double>(
      {static_cast<py::ssize_t>(frames.size()), py::ssize_t(3), py::ssize_t(3)});
  for (std::size_t i = 0; i < frames.size(); ++i) {
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(p.frames.mutable_data(i)) = frames[i];
  }
  return p;
}

py::array_t<double> from_isometry(const Eigen::Isometry3d& T) {
  py::array_t<double> out({py::ssize_t(4), py::ssize_t(4)});
  Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(out.mutable_data()) = T.matrix();
  return out;
}

py::array_t<double> from_isometries(const std::vector<Eigen::Isometry3d>& poses) {
  py::array_t<double> out({static_cast<py::ssize_t>(poses.size()), py::ssize_t(4), py::ssize_t(4)});
  for (std::size_t i = 0; i < poses.size(); ++i) {
    Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(out.mutable_data(i)) =
        poses[i].matrix();
  }
  return out;
}

}  // namespace loopscan::python
