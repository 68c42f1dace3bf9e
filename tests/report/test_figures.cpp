// The figures built on the plots: padded PR curves, legends outside the data, value-coloured
// lines with a colour bar, heat maps with axes, the paper's route figure and evo-style
// trajectory errors, each against a direct computation.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "loopscan/eval/precision_recall.hpp"
#include "loopscan/report/recognition_map.hpp"
#include "loopscan/report/report.hpp"
#include "loopscan/report/trajectory_error.hpp"
#include "report/svg_checks.hpp"

namespace lr = loopscan::report;
namespace ev = loopscan::eval;
using namespace loopscan::test;  // the SVG checks of svg_checks.hpp

namespace {

// y of the legend's box (its <rect> follows <g class="legend">).
double legend_top(const std::string& svg) {
  const std::size_t g = svg.find("<g class=\"legend\">");
  const std::size_t y = svg.find(" y=\"", g);
  return std::stod(svg.substr(y + 4));
}

double luminance(const std::string& hex) {
  const long v = std::strtol(hex.c_str() + 1, nullptr, 16);
  return 0.2126 * ((v >> 16) & 255) + 0.7152 * ((v >> 8) & 255) + 0.0722 * (v & 255);
}

}  // namespace

// Precision 1 and recall 0 are drawn inside the frame, not on it; ticks stay 0 .. 1.
TEST(ReportFigures, PrCurvesOnTheLimitsStayVisible) {
  const lr::Series perfect{"sc", {0.0, 0.5, 1.0}, {1.0, 1.0, 1.0}, ""};
  const std::string svg = lr::pr_curve_svg({perfect, {"m2dp", {0, 1}, {0.5, 0.2}, ""}}, "t");
  EXPECT_EQ(xml_problem(svg), "");
  lr::PlotOptions o;
  o.pad = 0.02;
  const lr::PlotFrame f = lr::make_frame({perfect}, o);
  for (const auto& [x, y] : line_points(path_data(svg).at(0))) {
    EXPECT_GT(y, f.top + 5.0);   // at least 5 px below the frame's top edge
    EXPECT_GT(x, f.left + 5.0);  // recall 0 right of the left edge
  }
  for (const char* tick : {">0<", ">0.2<", ">1<"}) EXPECT_EQ(count(svg, tick), 2u) << tick;
  EXPECT_EQ(count(svg, ">1.2<"), 0u);
  EXPECT_EQ(count(svg, ">-0.2<"), 0u);
  // The legend sits below the axis label, outside the plot area.
  EXPECT_GT(legend_top(svg), f.bottom + 40.0);
}

// An overlay is drawn with the plot's own frame: a mark at data (0.5, 0.5) lands on that pixel.
TEST(ReportFigures, OverlaysUseThePlotsFrame) {
  lr::PlotOptions o;
  o.overlay = [](const lr::PlotFrame& f) {
    return "<circle class=\"mark\" cx=\"" + lr::svg_px(f.to_px_x(0.5)) + "\" cy=\"" +
           lr::svg_px(f.to_px_y(0.5)) + "\" r=\"3\"/>\n";
  };
  const lr::Series s{"s", {0, 1}, {0, 1}, ""};
  const std::string svg = lr::line_plot_svg({s}, o);
  EXPECT_EQ(xml_problem(svg), "");
  const lr::PlotFrame f = lr::make_frame({s}, o);
  EXPECT_NE(svg.find("cx=\"" + lr::svg_px((f.left + f.right) / 2) + "\" cy=\"" +
                     lr::svg_px((f.top + f.bottom) / 2) + "\""),
            std::string::npos);
  EXPECT_LT(svg.find("class=\"mark\""), svg.find("class=\"legend\""));  // over the data
}

TEST(ReportFigures, ColourScaleRunsDarkToBright) {
  EXPECT_EQ(lr::scale_color(0.0), "#440154");
  EXPECT_EQ(lr::scale_color(1.0), "#fde725");
  EXPECT_EQ(lr::scale_color(-3.0), lr::scale_color(0.0));
  EXPECT_EQ(lr::scale_color(NAN), lr::scale_color(0.0));
  double previous = -1;
  for (int k = 0; k <= 40; ++k) {
    const double l = luminance(lr::scale_color(k / 40.0));
    EXPECT_GT(l, previous) << k;
    previous = l;
  }
}

// Every segment drawn once, in the colour step of its mean value; a colour bar with the label.
TEST(ReportFigures, ValueColouredLineCoversEverySegmentOnce) {
  lr::Series s{"estimate", {}, {}, ""};
  for (int i = 0; i <= 50; ++i) {
    s.x.push_back(i);
    s.y.push_back(std::sin(i * 0.2));
    s.value.push_back(i);  // 0 .. 50: low values dark, high values bright
  }
  lr::PlotOptions o;
  o.x_min = o.x_max = o.y_min = o.y_max = 0;
  o.color_label = "APE [m]";
  const std::string svg = lr::line_plot_svg({s}, o);
  EXPECT_EQ(xml_problem(svg), "");
  std::size_t segments = 0;
  for (const std::string& d : path_data(svg)) segments += count(d, "L");
  EXPECT_EQ(segments, 50u);
  EXPECT_NE(svg.find("<g class=\"colorbar\">"), std::string::npos);
  EXPECT_NE(svg.find(">APE [m]<"), std::string::npos);
  // The first segment (mean value 0.5) is in the darkest step, the last one in the brightest.
  const std::size_t first =
      svg.find("M" + lr::format_trimmed(lr::make_frame({s}, o).to_px_x(0), 2));
  ASSERT_NE(first, std::string::npos);
  const std::size_t stroke = svg.find("stroke=\"", first);  // of the path holding it
  EXPECT_EQ(svg.substr(stroke + 8, 7), lr::scale_color(0.5 / 24));
  // The last segment's path (the one ending at x = 50) has the brightest step's colour.
  const std::string last_end =
      " L" + lr::format_trimmed(lr::make_frame({s}, o).to_px_x(50), 2) + ",";
  const std::size_t last = svg.find(last_end);
  ASSERT_NE(last, std::string::npos);
  EXPECT_EQ(svg.substr(svg.find("stroke=\"", last) + 8, 7), lr::scale_color(23.5 / 24));
  // Without a value-coloured series: no colour bar, canvas as asked.
  s.value.clear();
  EXPECT_EQ(lr::line_plot_svg({s}, o).find("colorbar"), std::string::npos);
}

TEST(ReportFigures, HeatmapHasAxesInUnitsAndAColourBar) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(20, 60);
  m(0, 0) = 4.0;    // nearest ring, first sector: brightest
  m(19, 59) = 2.0;  // half way up the scale
  lr::HeatmapOptions o;
  o.title = "Scan Context";
  o.x_label = "azimuth [deg]";
  o.y_label = "distance [m]";
  o.colorbar_label = "height range [m]";
  o.x_first = -180;
  o.x_last = 180;
  o.y_last = 45;
  const std::string svg = lr::heatmap_svg(m, o);
  EXPECT_EQ(xml_problem(svg), "");
  // One rect per cell, 32 colour-bar steps and the bar's outline.
  EXPECT_EQ(count(svg, "<rect x="), 20u * 60u + 32u + 1u);
  EXPECT_EQ(count(svg, "<g class=\"colorbar\">"), 1u);
  for (const char* t : {">-150<", ">0<", ">150<", ">20<", ">40<", ">height range [m]<"})
    EXPECT_NE(svg.find(t), std::string::npos) << t;
  EXPECT_EQ(count(svg, "fill=\"" + lr::scale_color(1.0) + "\""), 1u);  // the one 4.0 cell
  EXPECT_EQ(count(svg, "fill=\"" + lr::scale_color(0.5) + "\""), 1u);  // the one 2.0 cell
  EXPECT_GE(count(svg, "fill=\"" + lr::scale_color(0.0) + "\""), 20u * 60u - 2u);
}

// Route figure against a hand-made evaluation: three revisits, two accepted at precision 1.
TEST(ReportFigures, RecognitionMapMarksAcceptedRevisitsAndLinksThem) {
  std::vector<Eigen::Vector3d> pos;
  for (int i = 0; i < 300; ++i) pos.emplace_back(i < 150 ? i : 300 - i, 0, 0);  // out and back
  const ev::Protocol protocol = ev::same_session_protocol();
  const ev::GroundTruth gt = ev::compute_ground_truth(pos, pos, protocol);
  ASSERT_GT(gt.n_loops, 3);
  // Queries 250, 260 match their true places, 270 a wrong one, ranked in that order.
  const std::vector<ev::QueryMatch> matches = {{250, 50, 0.1}, {260, 40, 0.2}, {270, 140, 0.3}};
  const ev::PrResult pr = ev::evaluate_matches(matches, pos, pos, protocol);
  ASSERT_EQ(lr::accepted_at_full_precision(pr), 2u);
  lr::RecognitionMap map;
  map.title = "out and back";
  map.query_pos = map.db_pos = pos;
  map.protocol = protocol;
  const std::string svg = lr::recognition_map_svg(map, pr);
  EXPECT_EQ(xml_problem(svg), "");
  EXPECT_NE(svg.find(">out and back: 2 of " + std::to_string(gt.n_loops) +
                     " revisits at 100% precision<"),
            std::string::npos);
  EXPECT_NE(svg.find("(" + std::to_string(gt.n_loops - 2) + ")<"), std::string::npos);  // missed
  const std::vector<std::string> d = path_data(svg);
  ASSERT_EQ(d.size(), 4u);          // route, missed, links, recognised
  EXPECT_EQ(count(d[2], "M"), 2u);  // one link per accepted match
  EXPECT_EQ(count(d[3], "M"), 4u);  // two strokes per recognised cross
  EXPECT_EQ(count(d[1], "M"), 2u * std::size_t(gt.n_loops - 2));
}

TEST(ReportFigures, TrajectoryErrorsAgainstADirectComputation) {
  std::vector<Eigen::Vector3d> gt, est;
  for (int i = 0; i < 100; ++i) {
    gt.emplace_back(i, 0.0, 0.5 * i);
    est.emplace_back(i, 0.01 * i, 0.5 * i + 0.02 * i);
  }
  const lr::TrajectoryErrors e = lr::trajectory_errors(gt, est);
  double sum = 0;
  for (int i = 0; i < 100; ++i) {
    const double err = std::hypot(0.01 * i, 0.02 * i);
    EXPECT_NEAR(e.error_m[i], err, 1e-12);
    EXPECT_NEAR(e.distance_m[i], i * std::hypot(1.0, 0.5), 1e-9);
    sum += err * err;
  }
  EXPECT_NEAR(e.rmse_m, std::sqrt(sum / 100), 1e-12);
  EXPECT_EQ(lr::top_view_axes(gt), (std::pair<int, int>{0, 2}));  // y is flat: x, z
  // Ties leave out y (down): a straight drive along x is drawn x against z, not height.
  const std::vector<Eigen::Vector3d> straight = {{0, 0, 0}, {36, 0, 0}};
  EXPECT_EQ(lr::top_view_axes(straight), (std::pair<int, int>{0, 2}));
  // North-east-down (RobotCar): down is flat, north and east are drawn.
  const std::vector<Eigen::Vector3d> ned = {{0, 0, 1}, {50, 20, 1.5}};
  EXPECT_EQ(lr::top_view_axes(ned), (std::pair<int, int>{0, 1}));
  EXPECT_THROW(lr::trajectory_errors(gt, {}), std::invalid_argument);

  lr::TrajectoryFigure f;
  f.title = "VO";
  f.gt = gt;
  f.estimate = est;
  const std::string map = lr::trajectory_error_map_svg(f);
  EXPECT_EQ(xml_problem(map), "");
  EXPECT_NE(map.find("(APE RMSE " + lr::format_fixed(e.rmse_m, 2) + " m)"), std::string::npos);
  EXPECT_NE(map.find("stroke-dasharray"), std::string::npos);  // the ground truth
  const std::string over = lr::error_over_distance_svg("error", gt, {{"VO", est}});
  EXPECT_EQ(xml_problem(over), "");
  EXPECT_NE(over.find(">distance travelled [m]<"), std::string::npos);
}
