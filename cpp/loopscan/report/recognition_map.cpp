#include "loopscan/report/recognition_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "loopscan/report/plot.hpp"
#include "loopscan/report/trajectory_error.hpp"

namespace loopscan::report {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// An "x" of half-size r at (x, y), as two strokes separated by NaN breaks.
void add_cross(Series& s, double x, double y, double r) {
  s.x.insert(s.x.end(), {x - r, x + r, kNaN, x - r, x + r, kNaN});
  s.y.insert(s.y.end(), {y - r, y + r, kNaN, y + r, y - r, kNaN});
}

}  // namespace

std::size_t accepted_at_full_precision(const eval::PrResult& pr) {
  return std::min(eval::full_precision_count(pr.curve), pr.ranked.size());
}

std::string recognition_map_svg(const RecognitionMap& map, const eval::PrResult& pr) {
  const std::pair<int, int> top = top_view_axes(map.db_pos);
  const int ax = map.x_axis >= 0 ? map.x_axis : top.first;
  const int ay = map.y_axis >= 0 ? map.y_axis : top.second;
  Series route = top_view_series("route", map.db_pos, {ax, ay}, "#c8c8c8");
  route.width = 3.0;
  // Marker size from the route's extent, so crosses read the same on any map.
  double extent = 1.0;
  if (!route.x.empty()) {
    const auto [x_lo, x_hi] = std::minmax_element(route.x.begin(), route.x.end());
    const auto [y_lo, y_hi] = std::minmax_element(route.y.begin(), route.y.end());
    extent = std::max({*x_hi - *x_lo, *y_hi - *y_lo, 1.0});
  }
  const double r = 0.008 * extent;

  const std::size_t n_accepted = accepted_at_full_precision(pr);
  std::vector<char> recognised(map.query_pos.size(), 0);
  Series links{"", {}, {}, "#ff7f0e"}, hits{"", {}, {}, "#d62728"}, missed{"", {}, {}, "#404040"};
  links.width = 1.0;
  hits.width = 2.0;
  missed.width = 1.2;
  for (std::size_t k = 0; k < n_accepted; ++k) {
    const eval::QueryMatch& m = pr.ranked[k].m;
    if (m.query < 0 || std::size_t(m.query) >= map.query_pos.size()) continue;
    recognised[std::size_t(m.query)] = 1;
    const Eigen::Vector3d& q = map.query_pos[std::size_t(m.query)];
    add_cross(hits, q[ax], q[ay], r);
    if (m.match < 0 || std::size_t(m.match) >= map.db_pos.size()) continue;
    const Eigen::Vector3d& p = map.db_pos[std::size_t(m.match)];
    links.x.insert(links.x.end(), {q[ax], p[ax], kNaN});
    links.y.insert(links.y.end(), {q[ay], p[ay], kNaN});
  }
  const eval::GroundTruth gt = eval::compute_ground_truth(map.query_pos, map.db_pos, map.protocol);
  int n_missed = 0;
  for (std::size_t i = 0; i < map.query_pos.size(); ++i) {
    if (!gt.is_loop[i] || recognised[i]) continue;
    ++n_missed;
    add_cross(missed, map.query_pos[i][ax], map.query_pos[i][ay], r);
  }
  const int n_hits = int(std::count(recognised.begin(), recognised.end(), 1));
  hits.name = "revisit recognised at 100% precision (" + std::to_string(n_hits) + ")";
  missed.name = "revisit missed (" + std::to_string(n_missed) + ")";
  links.name = "query - matched place";
  PlotOptions options;
  options.title = map.title + ": " + std::to_string(n_hits) + " of " + std::to_string(gt.n_loops) +
                  " revisits at 100% precision";
  options.x_label = axis_label(ax);
  options.y_label = axis_label(ay);
  options.x_min = options.x_max = options.y_min = options.y_max = 0;  // ranged from the data
  options.equal_aspect = true;
  return line_plot_svg({route, missed, links, hits}, options);
}

}  // namespace loopscan::report
