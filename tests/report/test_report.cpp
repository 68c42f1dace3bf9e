// SVG plots: well-formed markup, ticks, escaping, one path per series, data -> pixel mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "loopscan/report/html_page.hpp"
#include "loopscan/report/report.hpp"
#include "report/svg_checks.hpp"

namespace lr = loopscan::report;

using namespace loopscan::test;  // the SVG checks of svg_checks.hpp

namespace {

lr::Series diagonal() { return {"diag", {0.0, 0.5, 1.0}, {0.0, 0.5, 1.0}, ""}; }

// Inlined figures lose their XML declaration (not allowed inside HTML); captions are escaped.
TEST(ReportHtml, InlinesSvgWithoutTheXmlDeclaration) {
  lr::HtmlPage page;
  page.title = "t";
  lr::PlotOptions o;
  o.title = "plot";
  page.figures.push_back({"a < b", lr::line_plot_svg({{"s", {0, 1}, {0, 1}, ""}}, o)});
  ASSERT_EQ(page.figures[0].svg.rfind("<?xml", 0), 0u);  // the standalone file keeps it
  const std::string html = lr::render_html(page);
  EXPECT_EQ(html.find("<?xml"), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("a &lt; b"), std::string::npos);
}

}  // namespace

TEST(ReportText, EscapeAndFormat) {
  EXPECT_EQ(lr::xml_escape("a<b & \"c\" 'd'>"), "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;");
  EXPECT_EQ(lr::format_trimmed(0.6000000000000001, 1), "0.6");
  EXPECT_EQ(lr::format_trimmed(-1e-17, 2), "0");
  EXPECT_EQ(lr::format_trimmed(20.0, 0), "20");
  EXPECT_EQ(lr::format_fixed(1.0 / 3.0, 4), "0.3333");
  EXPECT_EQ(lr::utf8_length("a\xE2\x80\x94z"), 3u);
}

TEST(ReportTicks, NiceSteps) {
  const lr::Ticks unit = lr::nice_ticks(0.0, 1.0);
  ASSERT_EQ(unit.values.size(), 6u);
  EXPECT_NEAR(unit.values[3], 0.6, 1e-12);
  EXPECT_EQ(unit.decimals, 1);
  EXPECT_EQ(lr::nice_ticks(0.0, 37.0).values, (std::vector<double>{0, 10, 20, 30}));
  const lr::Ticks neg = lr::nice_ticks(-3.2, 4.7);  // raw step 1.58 -> 2
  EXPECT_EQ(neg.values, (std::vector<double>{-2, 0, 2, 4}));
  EXPECT_EQ(lr::nice_ticks(0.0, 0.05).decimals, 2);
  EXPECT_TRUE(lr::nice_ticks(1.0, 1.0).values.empty());
  EXPECT_TRUE(lr::nice_ticks(0.0, std::numeric_limits<double>::infinity()).values.empty());
}

TEST(ReportPlot, WellFormedWithTicksTitleAndLabels) {
  lr::PlotOptions opt;
  opt.title = "KITTI 00";
  const std::string svg = lr::line_plot_svg({diagonal()}, opt);
  EXPECT_EQ(xml_problem(svg), "");
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  // The plot area is the size asked for; the canvas grows below it by the legend.
  const lr::PlotFrame f = lr::make_frame({diagonal()}, opt);
  EXPECT_EQ(f.width, 640.0);
  EXPECT_GT(f.height, 480.0);
  EXPECT_EQ(f.bottom - f.top, lr::make_frame({lr::Series{"", {0, 1}, {0, 1}}}, opt).bottom - f.top);
  EXPECT_NE(svg.find("viewBox=\"0 0 640 " + lr::format_trimmed(f.height, 2) + "\""),
            std::string::npos);
  for (const char* tick : {">0<", ">0.2<", ">0.4<", ">0.6<", ">0.8<", ">1<"})
    EXPECT_EQ(count(svg, tick), 2u) << tick;  // once on each axis
  EXPECT_NE(svg.find(">KITTI 00<"), std::string::npos);
  EXPECT_NE(svg.find(">Recall<"), std::string::npos);
  EXPECT_NE(svg.find(">Precision<"), std::string::npos);
  EXPECT_NE(svg.find(">diag<"), std::string::npos);      // legend
  EXPECT_EQ(svg, lr::line_plot_svg({diagonal()}, opt));  // deterministic
  // The checker itself must catch broken markup.
  EXPECT_NE(xml_problem("<svg><g></svg>"), "");
  EXPECT_NE(xml_problem("<svg>a & b</svg>"), "");
}

TEST(ReportPlot, EscapesAllText) {
  lr::PlotOptions opt;
  opt.title = "<script> & \"quotes\"";
  opt.x_label = "a<b";
  lr::Series s = diagonal();
  s.name = "R&D 'x'";
  s.color = "red\"/><bad";
  const std::string svg = lr::line_plot_svg({s}, opt);
  EXPECT_EQ(xml_problem(svg), "");
  EXPECT_EQ(svg.find("<script>"), std::string::npos);
  EXPECT_NE(svg.find("&lt;script&gt; &amp; &quot;quotes&quot;"), std::string::npos);
  EXPECT_NE(svg.find(">a&lt;b<"), std::string::npos);
  EXPECT_NE(svg.find(">R&amp;D &apos;x&apos;<"), std::string::npos);
  EXPECT_EQ(svg.find("<bad"), std::string::npos);
}

TEST(ReportPlot, OnePathPerSeriesInBothModes) {
  const std::vector<lr::Series> three = {
      diagonal(), {"", {0, 1}, {1, 0}, "#000000"}, {"e", {}, {}, ""}};
  lr::PlotOptions opt;
  EXPECT_EQ(count(lr::line_plot_svg(three, opt), "<path"), 3u);
  opt.points = true;
  const std::string pts = lr::line_plot_svg(three, opt);
  EXPECT_EQ(xml_problem(pts), "");
  EXPECT_EQ(count(pts, "<path"), 3u);
  EXPECT_EQ(count(path_data(pts)[0], "M"), 3u);  // one marker per point
}

TEST(ReportPlot, PointsMapIntoTheFrame) {
  lr::PlotOptions opt;
  const lr::PlotFrame f = lr::make_frame({diagonal()}, opt);
  const std::string svg = lr::line_plot_svg({diagonal()}, opt);
  const auto pts = line_points(path_data(svg).at(0));
  ASSERT_EQ(pts.size(), 3u);
  // (0,0) is the lower-left corner of the frame, (1,1) the upper-right one.
  EXPECT_NEAR(pts[0].first, f.left, 0.01);
  EXPECT_NEAR(pts[0].second, f.bottom, 0.01);
  EXPECT_NEAR(pts[1].first, (f.left + f.right) / 2, 0.01);
  EXPECT_NEAR(pts[2].first, f.right, 0.01);
  EXPECT_NEAR(pts[2].second, f.top, 0.01);
  EXPECT_GT(f.left, 0.0);
  EXPECT_LT(f.right, 640.0);
  EXPECT_GT(f.top, 0.0);
  EXPECT_LT(f.bottom, 480.0);
}

TEST(ReportPlot, ClipsOutOfRangeAndBreaksAtNaN) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const lr::Series wild{
      "w", {-1.0, 0.5, 2.0, nan, 0.2, 0.3, 1e300}, {0.5, 0.5, 3.0, 0.1, 0.2, 0.3, 0.4}, ""};
  lr::PlotOptions opt;
  const lr::PlotFrame f = lr::make_frame({wild}, opt);
  const std::string d = path_data(lr::line_plot_svg({wild}, opt)).at(0);
  const auto pts = line_points(d);
  ASSERT_FALSE(pts.empty());
  for (const auto& [x, y] : pts) {
    EXPECT_GE(x, f.left - 0.01);
    EXPECT_LE(x, f.right + 0.01);
    EXPECT_GE(y, f.top - 0.01);
    EXPECT_LE(y, f.bottom + 0.01);
  }
  // Pieces: clipped entry + exit, the segment after the NaN, the segment towards 1e300.
  EXPECT_EQ(count(d, "M"), 2u);
  EXPECT_NEAR(pts.front().first, f.left, 0.01);  // entered through the left edge
}

TEST(ReportPlot, AutoRangeEqualAspect) {
  const lr::Series track{"track", {0, 100, 100, 0}, {0, 0, 10, 10}, ""};
  lr::PlotOptions opt;
  opt.x_min = opt.x_max = 0;
  opt.y_min = opt.y_max = 0;
  opt.equal_aspect = true;
  const lr::PlotFrame f = lr::make_frame({track}, opt);
  EXPECT_LE(f.x_min, 0.0);
  EXPECT_GE(f.x_max, 100.0);
  EXPECT_LE(f.y_min, 0.0);
  EXPECT_GE(f.y_max, 10.0);
  EXPECT_NEAR((f.x_max - f.x_min) / (f.right - f.left), (f.y_max - f.y_min) / (f.bottom - f.top),
              1e-12);
  const std::string svg = lr::map_plot_svg({track}, "trajectory");
  EXPECT_EQ(xml_problem(svg), "");
  EXPECT_NE(svg.find(">x [m]<"), std::string::npos);
  for (const auto& [x, y] : line_points(path_data(svg).at(0))) {
    EXPECT_GE(x, 0.0);
    EXPECT_LE(x, 640.0);
    EXPECT_GE(y, 0.0);
    EXPECT_LE(y, 480.0);
  }
  // No data at all still yields a valid plot.
  EXPECT_EQ(xml_problem(lr::map_plot_svg({}, "empty")), "");
}

// The hand example of test_eval: AUC = 7/36 = 0.1944, recall@100%P = 1/3.
TEST(ReportPr, TitleCarriesMetrics) {
  const std::vector<loopscan::eval::PrPoint> curve = {
      {1.0, 1.0 / 3.0}, {0.5, 1.0 / 3.0}, {2.0 / 3.0, 2.0 / 3.0}, {0.5, 2.0 / 3.0}};
  const lr::Series s = lr::pr_series(curve, "ours");
  EXPECT_EQ(lr::pr_metrics_text(s), "AUC=0.1944, recall@100%P=0.3333");
  const std::string one = lr::pr_curve_svg({s}, "KITTI 05");
  EXPECT_EQ(xml_problem(one), "");
  EXPECT_NE(one.find(">KITTI 05 \xE2\x80\x94 AUC=0.1944, recall@100%P=0.3333<"), std::string::npos);
  lr::Series other = s;
  other.name = "M2DP";
  const std::string two = lr::pr_curve_svg({s, other}, "KITTI 05");
  EXPECT_NE(two.find(">KITTI 05<"), std::string::npos);
  EXPECT_NE(two.find(">M2DP \xE2\x80\x94 AUC=0.1944, recall@100%P=0.3333<"), std::string::npos);
  EXPECT_EQ(count(two, "<path"), 2u);
}
