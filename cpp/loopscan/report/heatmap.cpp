#include "loopscan/report/heatmap.hpp"

#include <algorithm>
#include <cstdio>

#include "loopscan/report/svg_text.hpp"

namespace loopscan::report {

std::string heatmap_svg(const Eigen::MatrixXd& values, const std::string& title,
                        const std::string& x_label, const std::string& y_label, int cell_px) {
  const int rows = static_cast<int>(values.rows()), cols = static_cast<int>(values.cols());
  const int left = 50, top = 40, w = cols * cell_px, h = rows * cell_px;
  const double hi = values.size() > 0 ? std::max(values.maxCoeff(), 1e-12) : 1.0;
  std::string svg;
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
                "viewBox=\"0 0 %d %d\" font-family=\"sans-serif\">\n",
                w + left + 20, h + top + 50, w + left + 20, h + top + 50);
  svg += buf;
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  std::snprintf(buf, sizeof buf, "<text x=\"%d\" y=\"22\" font-size=\"15\" text-anchor=\"middle\">",
                left + w / 2);
  svg += buf + xml_escape(title) + "</text>\n";
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int g = 255 - static_cast<int>(std::clamp(values(r, c) / hi, 0.0, 1.0) * 255.0);
      std::snprintf(buf, sizeof buf,
                    "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"rgb(%d,%d,%d)\"/>\n",
                    left + c * cell_px, top + r * cell_px, cell_px, cell_px, g, g, g);
      svg += buf;
    }
  }
  std::snprintf(buf, sizeof buf,
                "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" "
                "stroke=\"black\"/>\n<text x=\"%d\" y=\"%d\" font-size=\"13\" "
                "text-anchor=\"middle\">",
                left, top, w, h, left + w / 2, top + h + 30);
  svg += buf + xml_escape(x_label) + "</text>\n";
  std::snprintf(buf, sizeof buf,
                "<text x=\"18\" y=\"%d\" font-size=\"13\" text-anchor=\"middle\" "
                "transform=\"rotate(-90 18 %d)\">",
                top + h / 2, top + h / 2);
  svg += buf + xml_escape(y_label) + "</text>\n</svg>\n";
  return svg;
}

}  // namespace loopscan::report
