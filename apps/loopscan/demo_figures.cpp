#include "demo_figures.hpp"

#include <cmath>
#include <limits>

#include "demo_opposite.hpp"
#include "evaluation_outputs.hpp"
#include "loopscan/report/heatmap.hpp"
#include "loopscan/report/plot.hpp"
#include "loopscan/report/pr_plot.hpp"

namespace loopscan::cli {
namespace {

std::string pr_figure(const DemoResults& r, bool cross, const std::string& title) {
  std::vector<report::Series> curves;
  for (const MethodResult& m : r.methods) {
    curves.push_back(report::pr_series((cross ? m.cross : m.same).pr.curve, method_name(m.method)));
  }
  return report::pr_curve_svg(curves, title);
}

// Route in gray; places recognised at 100% precision (Scan Context, winter vs summer) in red.
std::string route_figure(const DemoResults& r) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  report::Series route{"route", {}, {}, "#999999"},
      hits{"recognised at 100% precision", {}, {}, "#d62728"};
  for (const Eigen::Isometry3d& T : r.route->T_world_cam) {
    route.x.push_back(T.translation().x());
    route.y.push_back(T.translation().z());
  }
  const MethodResult& sc = r.methods.front();
  const auto& ranked = sc.cross.pr.ranked;
  std::size_t last_exact = 0;  // matches up to the last rank with precision 1
  for (std::size_t k = 0; k < sc.cross.pr.curve.size(); ++k) {
    if (sc.cross.pr.curve[k].precision == 1.0) last_exact = k + 1;
  }
  for (std::size_t k = 0; k < last_exact && k < ranked.size(); ++k) {
    const Eigen::Vector3d& p = sc.query_positions[ranked[k].m.query];
    for (double d : {-2.5, 2.5}) {  // a small cross per place, separated by NaN breaks
      hits.x.push_back(p.x() + d);
      hits.y.push_back(p.z() + d);
    }
    hits.x.push_back(nan);
    hits.y.push_back(nan);
    hits.x.push_back(p.x() - 2.5);
    hits.y.push_back(p.z() + 2.5);
    hits.x.push_back(p.x() + 2.5);
    hits.y.push_back(p.z() - 2.5);
    hits.x.push_back(nan);
    hits.y.push_back(nan);
  }
  return report::map_plot_svg({route, hits},
                              "Scan Context, winter queries vs summer map: places recognised at "
                              "100% precision");
}

std::string scan_figure(const ExampleScan& e) {
  report::Series pts{"imitated scan", {}, {}, "#1f77b4"};
  for (const PointI& q : e.scan) {
    pts.x.push_back(q.p.x());
    pts.y.push_back(q.p.z());
  }
  report::PlotOptions o;
  o.title = "Imitated LiDAR scan, top view (keyframe " + std::to_string(e.keyframe_id) + ")";
  o.x_label = "x (right) [m]";
  o.y_label = "z (forward) [m]";
  o.x_min = o.x_max = o.y_min = o.y_max = 0;  // ranged from the data
  o.points = true;
  o.equal_aspect = true;
  return report::line_plot_svg({pts}, o);
}

std::string scan_context_figure(const ExampleScan& e) {
  const int rings = 20, sectors = 60;
  Eigen::MatrixXd image(rings, sectors);
  for (int s = 0; s < sectors; ++s) {
    for (int r = 0; r < rings; ++r) image(r, s) = e.scan_context(0, s * rings + r);
  }
  return report::heatmap_svg(image, "Scan Context (structure: height range per bin)",
                             "sector (6 deg each)", "ring (2.25 m each)");
}

}  // namespace

ExampleScan example_scan(const sim::VoOutput& vo, const SequenceOptions& options) {
  ExampleScan e;
  if (vo.poses.empty()) return e;
  const int middle = vo.poses[vo.poses.size() / 2].id;
  std::map<int, Cloud> scans = scans_at(vo, options.imitation, {middle});
  if (scans.empty()) return e;
  e.keyframe_id = middle;
  e.scan = std::move(scans[middle]);
  e.scan_context = describe(Method::ScanContext, e.scan, options.descriptors);
  return e;
}

report::HtmlPage demo_page(const DemoResults& r) {
  report::HtmlPage page;
  page.title = "loopscan demo: the built-in city, summer and winter";
  page.paragraphs.push_back(
      "One synthetic world, driven twice: a summer session (the map) and a winter session "
      "(queries). Same-season: summer against itself (10 m, index mask 100). Cross-season: winter "
      "keyframes against the summer map (25 m, no mask), the paper's RobotCar protocol. Default "
      "mode, one exact difference-matrix row per query.");
  report::Table t;
  t.caption = "Accuracy and run time (ms per keyframe / per query, one thread)";
  t.header = {"method",       "AUC same", "R@100P same", "F1 same",     "AUC cross",
              "R@100P cross", "F1 cross", "imitate ms",  "describe ms", "query ms"};
  for (const MethodResult& m : r.methods) {
    t.rows.push_back({method_name(m.method), fixed(m.same.pr.auc, 4),
                      fixed(m.same.pr.recall_at_100_precision, 4), fixed(m.same.pr.f1_max, 4),
                      fixed(m.cross.pr.auc, 4), fixed(m.cross.pr.recall_at_100_precision, 4),
                      fixed(m.cross.pr.f1_max, 4), fixed(m.imitate_ms, 3), fixed(m.describe_ms, 3),
                      fixed(m.same.query_ms, 3)});
  }
  page.tables.push_back(t);
  report::Table d;
  d.caption =
      "By direction of the revisit (top-1 correct / ground-truth loops, AUC): same direction = "
      "headings less than 90 degrees apart";
  d.header = {"method",    "session pair",    "same: top-1",
              "same: AUC", "opposite: top-1", "opposite: AUC"};
  for (const MethodResult& m : r.methods) {
    for (const auto& [name, split] : {std::pair{"summer vs summer", &m.same_by_direction},
                                      std::pair{"winter vs summer", &m.cross_by_direction}}) {
      std::vector<std::string> row = {method_name(m.method), name};
      for (std::string& c : direction_cells(*split)) row.push_back(std::move(c));
      d.rows.push_back(std::move(row));
    }
  }
  page.tables.push_back(d);
  page.figures.push_back(
      {"Precision-recall, summer vs summer", pr_figure(r, false, "Same season")});
  page.figures.push_back(
      {"Precision-recall, winter vs summer", pr_figure(r, true, "Cross season")});
  page.figures.push_back({"Route and recognised places", route_figure(r)});
  page.figures.push_back({"One imitated scan", scan_figure(r.example)});
  page.figures.push_back({"Its Scan Context", scan_context_figure(r.example)});
  page.figures.insert(page.figures.end(), r.opposite.begin(), r.opposite.end());
  return page;
}

}  // namespace loopscan::cli
