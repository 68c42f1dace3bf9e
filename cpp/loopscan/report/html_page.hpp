#pragma once
// A self-contained HTML report: a title, tables and inline SVG figures.
#include <string>
#include <vector>

namespace loopscan::report {

struct Table {
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

struct Figure {
  std::string caption;
  std::string svg;  // a complete <svg> document, inlined
};

struct HtmlPage {
  std::string title;
  std::vector<std::string> paragraphs;  // plain text, escaped
  std::vector<Table> tables;
  std::vector<Figure> figures;
};

std::string render_html(const HtmlPage& page);

}  // namespace loopscan::report
