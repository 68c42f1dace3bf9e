#include "demo/opposite.hpp"

#include <algorithm>
#include <cmath>

#include "loopscan/report/plot.hpp"

namespace loopscan::cli {

std::map<int, Cloud> scans_at(const sim::VoOutput& vo, const ImitationConfig& imitation,
                              const std::vector<int>& keyframe_ids) {
  std::map<int, Cloud> out;
  ScanImitator imitator(imitation);
  std::vector<ReadyScan> ready;
  auto take = [&] {
    for (ReadyScan& r : ready) {
      if (std::find(keyframe_ids.begin(), keyframe_ids.end(), r.keyframe.id) != keyframe_ids.end())
        out[r.keyframe.id] = std::move(r.scan);
    }
    ready.clear();
  };
  std::size_t next = 0;
  for (const KeyframePose& k : vo.poses) {
    if (out.size() == keyframe_ids.size()) return out;
    const std::size_t first = next;
    while (next < vo.points.size() && vo.points[next].id <= k.id) ++next;
    imitator.push(k, vo.points.data() + first, next - first, false, ScanFilter::Cartesian, ready);
    take();
  }
  imitator.finish(ScanFilter::Cartesian, ready);
  take();
  return out;
}

namespace {

report::Series world_series(const Cloud& scan, const Eigen::Isometry3d& T_world_cam,
                            const std::string& name, const std::string& color) {
  report::Series s{name, {}, {}, color};
  for (const PointI& q : scan) {
    const Eigen::Vector3d p = T_world_cam * q.p;
    s.x.push_back(p.x());
    s.y.push_back(p.z());
  }
  return s;
}

// The camera and its heading: a dotted 6 m arrow.
report::Series camera_series(const Eigen::Isometry3d& T, const std::string& name,
                             const std::string& color) {
  const Eigen::Vector3d c = T.translation(), f = T.linear().col(2);
  report::Series s{name, {}, {}, color};
  for (double d = 0; d <= 6.0; d += 0.25) {
    s.x.push_back(c.x() + d * f.x());
    s.y.push_back(c.z() + d * f.z());
  }
  return s;
}

std::string figure(const sim::Trajectory& route, const sim::VoOutput& vo, std::pair<int, int> p,
                   const ImitationConfig& imitation, const std::string& title) {
  const Eigen::Isometry3d& A = route.T_world_cam[static_cast<std::size_t>(p.first)];
  const Eigen::Isometry3d& B = route.T_world_cam[static_cast<std::size_t>(p.second)];
  std::map<int, Cloud> scans = scans_at(vo, imitation, {p.first, p.second});
  const std::vector<report::Series> series = {
      world_series(scans[p.first], A, "first drive, keyframe " + std::to_string(p.first),
                   "#1f77b4"),
      world_series(scans[p.second], B, "return, keyframe " + std::to_string(p.second), "#ff7f0e"),
      camera_series(A, "camera and heading, first drive", "#08306b"),
      camera_series(B, "camera and heading, return", "#d62728")};
  report::PlotOptions o;
  o.title = title;
  o.x_label = "x [m]";
  o.y_label = "z [m]";
  o.x_min = o.x_max = o.y_min = o.y_max = 0;  // ranged from the data
  o.points = true;
  o.equal_aspect = true;
  return report::line_plot_svg(series, o);
}

}  // namespace

std::vector<Eigen::Vector3d> headings_of(const sim::Trajectory& route,
                                         const std::vector<int>& ids) {
  std::vector<Eigen::Vector3d> out;
  for (int id : ids) out.push_back(route.T_world_cam[static_cast<std::size_t>(id)].linear().col(2));
  return out;
}

std::pair<int, int> opposite_revisit(const sim::Trajectory& route, const std::vector<int>& ids,
                                     int gap) {
  std::pair<int, int> best{-1, -1};
  double best_score = 1e300;
  const double middle = static_cast<double>(ids.size()) * 0.75;  // return drives come late
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const Eigen::Isometry3d& Q = route.T_world_cam[static_cast<std::size_t>(ids[i])];
    for (std::size_t j = 0; j + gap <= i; ++j) {
      const Eigen::Isometry3d& R = route.T_world_cam[static_cast<std::size_t>(ids[j])];
      if ((Q.translation() - R.translation()).norm() > 5.0) continue;
      if (Q.linear().col(2).dot(R.linear().col(2)) > std::cos(170.0 * M_PI / 180.0)) continue;
      const double score = std::abs(static_cast<double>(i) - middle);
      if (score < best_score) {
        best_score = score;
        best = {ids[j], ids[i]};
      }
    }
  }
  return best;
}

std::vector<report::Figure> opposite_figures(const sim::Trajectory& route, const sim::VoOutput& vo,
                                             std::pair<int, int> pair) {
  if (pair.first < 0) return {};
  ImitationConfig forward;  // the paper's scan, as the default mode uses it
  ImitationConfig two_sided;
  two_sided.lookahead_m = 20;
  return {{"An opposite-direction revisit: the paper's forward-only scans",
           figure(route, vo, pair, forward,
                  "Forward-only scans of one place, driven both ways (world frame, top view)")},
          {"The same revisit with two-sided scans (--lookahead 20)",
           figure(route, vo, pair, two_sided,
                  "Two-sided scans of the same place (world frame, top view)")}};
}

}  // namespace loopscan::cli
