#pragma once
// evo-style trajectory figures: the ground truth and an estimate coloured by its position error
// (APE), and the error over the distance travelled.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "loopscan/report/plot.hpp"

namespace loopscan::report {

struct TrajectoryErrors {
  std::vector<double> distance_m;  // along the ground truth, from its first position
  std::vector<double> error_m;     // |gt_i - estimate_i| per position
  double rmse_m = 0;
};

// Per-position errors of `estimate` against `gt` as given (align them first if needed).
// Throws std::invalid_argument on different sizes.
TrajectoryErrors trajectory_errors(const std::vector<Eigen::Vector3d>& gt,
                                   const std::vector<Eigen::Vector3d>& estimate);

// The two horizontal axes of largest spread (e.g. x, z for camera-frame KITTI poses, x, y for
// RobotCar's north-east-down), in ascending order.
std::pair<int, int> top_view_axes(const std::vector<Eigen::Vector3d>& positions);

// "x [m]", "y [m]" or "z [m]".
const char* axis_label(int axis);

// The positions' coordinates `axes` (e.g. top_view_axes) as a plot series.
Series top_view_series(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                       std::pair<int, int> axes, const std::string& color = "");

struct TrajectoryFigure {
  std::string title;
  std::vector<Eigen::Vector3d> gt, estimate;  // same length, same frame
  std::string estimate_name = "estimate";
  // Extra series in the same top-view coordinates: under the estimate (e.g. the trajectory
  // before a correction) and on top of it (e.g. loops).
  std::vector<Series> underlays, overlays;
};

// Map: ground truth dashed, the estimate coloured by APE with a colour bar (m).
std::string trajectory_error_map_svg(const TrajectoryFigure& figure);

// APE over the distance travelled, one line per (name, estimate) against the same ground truth.
std::string error_over_distance_svg(
    const std::string& title, const std::vector<Eigen::Vector3d>& gt,
    const std::vector<std::pair<std::string, std::vector<Eigen::Vector3d>>>& estimates);

}  // namespace loopscan::report
