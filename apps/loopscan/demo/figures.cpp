#include "demo/figures.hpp"

#include <cmath>

#include "demo/opposite.hpp"
#include "loopscan/report/frame.hpp"
#include "loopscan/report/heatmap.hpp"
#include "loopscan/report/plot.hpp"
#include "loopscan/report/pr_plot.hpp"
#include "loopscan/report/recognition_map.hpp"
#include "loopscan/report/svg_text.hpp"
#include "outputs/evaluation.hpp"

namespace loopscan::cli {
namespace {

std::string pr_figure(const DemoResults& r, bool cross, const std::string& title) {
  std::vector<report::Series> curves;
  for (const MethodResult& m : r.methods) {
    curves.push_back(report::pr_series((cross ? m.cross : m.same).pr.curve, method_name(m.method)));
  }
  return report::pr_curve_svg(curves, title);
}

// The paper's route figure for Scan Context, one session pair.
std::string route_figure(const DemoResults& r, const MethodResult& sc, bool cross) {
  report::RecognitionMap map;
  map.title =
      cross ? "Scan Context, winter queries vs summer map" : "Scan Context, summer vs summer";
  map.query_pos = cross ? sc.query_positions : sc.map_positions;
  map.db_pos = sc.map_positions;
  map.protocol = cross ? r.cross_season : r.same_season;
  return report::recognition_map_svg(map, (cross ? sc.cross : sc.same).pr);
}

// Top view of the scan with the sensor as a triangle pointing along its heading (+z, ahead).
std::string scan_figure(const ExampleScan& e) {
  report::Series pts{"imitated scan point", {}, {}, "#1f77b4"};
  for (const PointI& q : e.scan) {
    pts.x.push_back(q.p.x());
    pts.y.push_back(q.p.z());
  }
  report::PlotOptions o;
  o.title = "Imitated LiDAR scan, top view (keyframe " + std::to_string(e.keyframe_id) + ")";
  o.x_label = "x (right) [m]";
  o.y_label = "z (ahead) [m]";
  o.x_min = o.x_max = o.y_min = o.y_max = 0;  // ranged from the data
  o.points = true;
  o.equal_aspect = true;
  // The sensor: a triangle at the origin pointing ahead (+z), over the points.
  o.overlay = [](const report::PlotFrame& f) {
    using report::svg_px;
    const double cx = f.to_px_x(0), cy = f.to_px_y(0), s = 9;
    return "<g class=\"sensor\"><path d=\"M" + svg_px(cx) + "," + svg_px(cy - 1.6 * s) + " L" +
           svg_px(cx - s) + "," + svg_px(cy + s) + " L" + svg_px(cx + s) + "," + svg_px(cy + s) +
           " Z\" fill=\"#d62728\" stroke=\"black\"/>\n" +
           report::svg_text(cx + s + 4, cy + s, "start", "sensor, heading +z",
                            " fill=\"#d62728\" stroke=\"white\" stroke-width=\"3\" "
                            "paint-order=\"stroke\"") +
           "</g>\n";
  };
  return report::line_plot_svg({pts}, o);
}

// One half of the default Scan Context (row 0, the place itself) as rings x sectors.
std::string scan_context_figure(const ExampleScan& e, bool intensity) {
  const ScanContextConfig& c = e.config;
  const int rings = c.rings, sectors = c.sectors, offset = intensity ? rings * sectors : 0;
  Eigen::MatrixXd image(rings, sectors);
  for (int s = 0; s < sectors; ++s) {
    for (int r = 0; r < rings; ++r) image(r, s) = e.scan_context(0, offset + s * rings + r);
  }
  report::HeatmapOptions o;
  o.title = intensity ? "Scan Context, intensity half: bin brighter than the scan's mean gray"
                      : "Scan Context, structure half: height range per bin";
  o.x_label = "azimuth [deg] (0 = right, 90 = ahead, 180 = left)";
  o.y_label = "distance from the sensor [m]";
  o.colorbar_label = intensity ? "brighter (1) or not (0)" : "height range [m]";
  o.x_first = -180;  // sector 0 starts at atan2(ahead, right) = -180 deg
  o.x_last = 180;
  o.y_first = 0;  // ring 0 (nearest) on top
  o.y_last = c.max_radius_m;
  if (intensity) o.hi = 1;
  return report::heatmap_svg(image, o);
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
  e.config = options.descriptors.scan_context;
  return e;
}

report::HtmlPage demo_page(const DemoResults& r) {
  report::HtmlPage page;
  page.title = "loopscan demo: " + r.route->name + ", summer and winter";
  page.paragraphs.push_back(
      "One synthetic world, driven twice: a summer session (the map) and a winter session "
      "(queries). Same-season: summer against itself (" +
      protocol_text(r.same_season) + "). Cross-season: winter keyframes against the summer map (" +
      protocol_text(r.cross_season) + "), the paper's RobotCar protocol. " +
      (r.mode == Mode::Reference ? "Reference" : "Default") +
      " mode, one exact difference-matrix row per query.");
  report::Table t;
  t.caption = "Accuracy and run time (ms per keyframe / per query, " + std::to_string(r.threads) +
              (r.threads == 1 ? " thread)" : " threads)");
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
  page.figures.push_back({"Places recognised by Scan Context, summer vs summer",
                          route_figure(r, r.methods.front(), false)});
  page.figures.push_back({"Places recognised by Scan Context, winter vs summer",
                          route_figure(r, r.methods.front(), true)});
  page.figures.push_back({"One imitated scan", scan_figure(r.example)});
  page.figures.push_back({"Its Scan Context, structure", scan_context_figure(r.example, false)});
  page.figures.push_back({"Its Scan Context, intensity", scan_context_figure(r.example, true)});
  page.figures.insert(page.figures.end(), r.opposite.begin(), r.opposite.end());
  return page;
}

}  // namespace loopscan::cli
