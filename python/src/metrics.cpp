// Trajectory readers (KITTI, TUM) and the odometry metrics (KITTI drift, ATE, evo's RPE).
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "loopscan/eval/loop_metrics.hpp"
#include "loopscan/eval/odometry_metrics.hpp"
#include "loopscan/io/ground_truth_files.hpp"

namespace loopscan::python {

namespace {

// (N, 3, 4) or (N, 4, 4) camera-to-world poses.
std::vector<Eigen::Isometry3d> to_isometries(const DoubleArray& a, const std::string& name) {
  if (!(a.ndim() == 3 && (a.shape(1) == 3 || a.shape(1) == 4) && a.shape(2) == 4))
    require_shape(a, name, {-1, 3, 4}, "camera-to-world poses, 3x4 or 4x4 each");
  std::vector<Eigen::Isometry3d> out(static_cast<std::size_t>(a.shape(0)));
  const auto v = a.unchecked<3>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = v(i, r, c);
    out[static_cast<std::size_t>(i)].matrix() = m;
  }
  return out;
}

}  // namespace

void bind_metrics(py::module_& m) {
  m.def(
      "read_kitti_poses",
      [](const std::string& path) {
        std::vector<Eigen::Isometry3d> poses;
        for (const auto& T : io::read_kitti_poses(path)) {
          poses.emplace_back();
          poses.back().matrix().topRows<3>() = T;
        }
        return from_isometries(poses);
      },
      py::arg("path"), "KITTI poses (camera-to-world, a line per frame) -> float64 (N, 4, 4).");
  m.def(
      "read_tum",
      [](const std::string& path) {
        const std::vector<io::TumPose> tum = io::read_tum_trajectory(path);
        py::array_t<double> times(static_cast<py::ssize_t>(tum.size()));
        std::vector<Eigen::Isometry3d> poses;
        for (std::size_t i = 0; i < tum.size(); ++i) {
          times.mutable_at(i) = tum[i].time;
          poses.push_back(tum[i].T_world_body);
        }
        return py::make_tuple(times, from_isometries(poses));
      },
      py::arg("path"), "TUM trajectory -> (times (N,), T_world_body float64 (N, 4, 4)).");
  m.def(
      "odometry_metrics",
      [](const DoubleArray& gt, const DoubleArray& estimate, std::vector<double> lengths_m,
         int step_frames) {
        eval::OdometryOptions o;
        if (!lengths_m.empty()) o.segment_lengths_m = lengths_m;
        o.step_frames = step_frames;
        const auto g = to_isometries(gt, "gt"), e = to_isometries(estimate, "estimate");
        eval::OdometryMetrics r;
        {
          py::gil_scoped_release release;
          r = eval::odometry_metrics(g, e, o);
        }
        py::dict d;
        d["segments"] = r.segments;
        d["translation_percent"] = r.translation_percent;
        d["rotation_deg_per_100m"] = r.rotation_deg_per_100m;
        d["ate_rmse_m"] = r.ate_rmse_m;
        d["sim3_scale"] = r.sim3_scale;
        d["ate_sim3_rmse_m"] = r.ate_sim3_rmse_m;
        d["path_length_m"] = r.path_length_m;
        d["end_point_error_percent"] = r.end_point_error_percent;
        d["lengths_m"] = r.lengths_m;
        d["translation_percent_by_length"] = r.translation_percent_by_length;
        d["rotation_deg_per_100m_by_length"] = r.rotation_deg_per_100m_by_length;
        return d;
      },
      py::arg("gt"), py::arg("estimate"), py::arg("lengths_m") = std::vector<double>{},
      py::arg("step_frames") = 10,
      "KITTI's odometry metrics (segments of 100..800 m every 10th frame by default) and the "
      "ATE after rigid alignment; poses camera-to-world, (N, 3, 4) or (N, 4, 4).");
  m.def(
      "relative_pose_error",
      [](const DoubleArray& gt, const DoubleArray& estimate, double delta_m) {
        const eval::RelativeError r = eval::relative_pose_error(
            to_isometries(gt, "gt"), to_isometries(estimate, "estimate"), delta_m);
        py::dict d;
        d["pairs"] = r.pairs;
        d["translation_rmse_m"] = r.translation_rmse_m;
        d["rotation_rmse_deg"] = r.rotation_rmse_deg;
        return d;
      },
      py::arg("gt"), py::arg("estimate"), py::arg("delta_m"),
      "evo's `evo_rpe --delta D --delta_unit m`: RMSE of the relative poses every D metres.");
}

}  // namespace loopscan::python
