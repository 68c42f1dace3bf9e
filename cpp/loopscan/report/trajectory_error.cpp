#include "loopscan/report/trajectory_error.hpp"

#include <cmath>
#include <stdexcept>

#include "loopscan/report/svg_text.hpp"

namespace loopscan::report {

TrajectoryErrors trajectory_errors(const std::vector<Eigen::Vector3d>& gt,
                                   const std::vector<Eigen::Vector3d>& estimate) {
  if (gt.size() != estimate.size()) {
    throw std::invalid_argument("trajectory_errors: " + std::to_string(gt.size()) +
                                " ground-truth positions but " + std::to_string(estimate.size()) +
                                " estimated ones");
  }
  TrajectoryErrors e;
  double travelled = 0, sum_sq = 0;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    if (i > 0) travelled += (gt[i] - gt[i - 1]).norm();
    e.distance_m.push_back(travelled);
    e.error_m.push_back((gt[i] - estimate[i]).norm());
    sum_sq += e.error_m.back() * e.error_m.back();
  }
  e.rmse_m = gt.empty() ? 0.0 : std::sqrt(sum_sq / double(gt.size()));
  return e;
}

std::pair<int, int> top_view_axes(const std::vector<Eigen::Vector3d>& positions) {
  if (positions.empty()) return {0, 2};
  Eigen::Vector3d lo = positions[0], hi = lo;
  for (const Eigen::Vector3d& p : positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Eigen::Vector3d spread = hi - lo;
  int smallest = 1;  // the axis left out: the one with the least spread, y (down) on ties
  for (int a : {0, 2}) {
    if (spread[a] < spread[smallest]) smallest = a;
  }
  if (smallest == 0) return {1, 2};
  if (smallest == 1) return {0, 2};
  return {0, 1};
}

Series top_view_series(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                       std::pair<int, int> axes, const std::string& color) {
  Series s{name, {}, {}, color};
  for (const Eigen::Vector3d& v : positions) {
    s.x.push_back(v[axes.first]);
    s.y.push_back(v[axes.second]);
  }
  return s;
}

const char* axis_label(int axis) {
  static const char* const labels[] = {"x [m]", "y [m]", "z [m]"};
  return labels[axis];
}

namespace {}  // namespace

std::string trajectory_error_map_svg(const TrajectoryFigure& f) {
  const TrajectoryErrors e = trajectory_errors(f.gt, f.estimate);
  const std::pair<int, int> axes = top_view_axes(f.gt);
  const auto [ax, ay] = axes;
  Series truth = top_view_series("ground truth", f.gt, axes, "#222222");
  truth.dash = "6,4";
  truth.width = 1.2;
  Series estimate = top_view_series(f.estimate_name + " (colour: APE)", f.estimate, axes);
  estimate.value = e.error_m;
  estimate.width = 2.5;
  std::vector<Series> all = {truth};
  all.insert(all.end(), f.underlays.begin(), f.underlays.end());
  all.push_back(estimate);
  all.insert(all.end(), f.overlays.begin(), f.overlays.end());
  PlotOptions o;
  o.title = f.title + " (APE RMSE " + format_fixed(e.rmse_m, 2) + " m)";
  o.x_label = axis_label(ax);
  o.y_label = axis_label(ay);
  o.x_min = o.x_max = o.y_min = o.y_max = 0;
  o.equal_aspect = true;
  o.color_label = "APE [m]";
  o.color_min = 0;
  o.color_max = 0;
  for (const double v : e.error_m) o.color_max = std::max(o.color_max, v);
  if (!(o.color_max > 0)) o.color_max = 1;
  return line_plot_svg(all, o);
}

std::string error_over_distance_svg(
    const std::string& title, const std::vector<Eigen::Vector3d>& gt,
    const std::vector<std::pair<std::string, std::vector<Eigen::Vector3d>>>& estimates) {
  std::vector<Series> lines;
  double top = 0;
  for (const auto& [name, estimate] : estimates) {
    const TrajectoryErrors e = trajectory_errors(gt, estimate);
    lines.push_back(
        {name + " (RMSE " + format_fixed(e.rmse_m, 2) + " m)", e.distance_m, e.error_m, ""});
    for (const double v : e.error_m) top = std::max(top, v);
  }
  PlotOptions o;
  o.title = title;
  o.x_label = "distance travelled [m]";
  o.y_label = "APE [m]";
  o.x_min = o.x_max = 0;  // x ranged from the data
  o.y_min = 0;
  o.y_max = top > 0 ? top * 1.05 : 1.0;
  o.height = 320;
  return line_plot_svg(lines, o);
}

}  // namespace loopscan::report
